// The bytes of the messages ranks exchange: fixed-size values and arrays of doubles in this
// machine's byte order (every rank of a job runs the same build, on the same kind of node).
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "farfield/farfield.hpp"

namespace fird::distributed {

using Bytes = std::vector<unsigned char>;

struct Writer {
    Bytes bytes;
    template <class T> void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const unsigned char*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    void put(std::span<const double> values) {
        const auto* p = reinterpret_cast<const unsigned char*>(values.data());
        bytes.insert(bytes.end(), p, p + values.size_bytes());
    }
    void put(const std::string& text) {
        put(std::uint64_t(text.size()));
        bytes.insert(bytes.end(), text.begin(), text.end());
    }
    // A far field, or none.
    void put(const FarField* farfield) {
        put(std::uint8_t(farfield ? 1 : 0));
        if (!farfield) return;
        put(farfield->width);
        put(farfield->height);
        put(std::span<const double>(farfield->lm));
    }
};

struct Reader {
    const Bytes& bytes;
    std::size_t at = 0;
    void take(void* out, std::size_t n) {
        if (at + n > bytes.size()) throw std::runtime_error("a message between ranks is cut short");
        if (n > 0) std::memcpy(out, bytes.data() + at, n);
        at += n;
    }
    template <class T> T get() {
        T v;
        take(&v, sizeof(T));
        return v;
    }
    void get(std::span<double> out) { take(out.data(), out.size_bytes()); }
    std::string text() {
        std::string s(get<std::uint64_t>(), '\0');
        take(s.data(), s.size());
        return s;
    }
    std::optional<FarField> farfield() {
        if (get<std::uint8_t>() == 0) return std::nullopt;
        FarField f;
        f.width = get<std::uint32_t>();
        f.height = get<std::uint32_t>();
        f.lm.resize(std::size_t(f.width) * f.height);
        get(f.lm);
        return f;
    }
};

} // namespace fird::distributed
