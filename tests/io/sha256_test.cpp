// The digest --resume records for the files a scene names is SHA-256 itself: FIPS 180-2's
// published examples (appendix B) and the empty message give the published digests, and a
// file (read in 64 KiB pieces) gives the digest of its bytes read at once.
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "io/sha256.hpp"

namespace fird::test {
namespace {

TEST(Sha256, PublishedDigests) {
    EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256_hex("abc"),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    // Two blocks: the padding starts a block of its own.
    EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, AFileHasTheDigestOfItsBytes) {
    const std::string path = ::testing::TempDir() + "/fird_sha256_test.bin";
    // One million 'a' spans 15 whole 64 KiB reads and a partial one; 65536 bytes end
    // exactly on a read (the last read is empty).
    for (std::size_t bytes : {std::size_t(1000000), std::size_t(65536), std::size_t(0)}) {
        std::ofstream(path, std::ios::binary) << std::string(bytes, 'a');
        EXPECT_EQ(file_sha256_hex(path), sha256_hex(std::string(bytes, 'a'))) << bytes;
    }
    EXPECT_EQ(file_sha256_hex(path),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    std::filesystem::remove(path);
    try {
        (void)file_sha256_hex(path);
        ADD_FAILURE() << "a missing file was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path + ": cannot open"), std::string::npos);
    }
}

} // namespace
} // namespace fird::test
