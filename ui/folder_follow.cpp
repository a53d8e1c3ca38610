#include "folder_follow.hpp"

#include <chrono>
#include <filesystem>

#include <fmt/format.h>

namespace fird::ui {

namespace {

constexpr double kReadInterval_s = 1.0;
// After an interrupted end: slower, in case a resumed run continues it in the folder.
constexpr double kInterruptedReadInterval_s = 5.0;

// One read: how the search began the first time, then what it wrote since (a copy, so the
// search a frame shows never changes under it).
FollowRead read(const std::string& dir, std::shared_ptr<const FollowedSearch> before) {
    FollowRead r;
    std::error_code ec;
    r.scene_toml = std::filesystem::is_regular_file(std::filesystem::path(dir) / "scene.toml", ec);
    if (!before) {
        if (search_began(dir))
            r.search = std::make_shared<const FollowedSearch>(read_search_folder(dir));
        return r;
    }
    auto next = std::make_shared<FollowedSearch>(*before);
    refresh_search_folder(*next);
    r.search = std::move(next);
    return r;
}

bool ready(const std::future<FollowRead>& f) {
    return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

bool interrupted(const FolderFollow& f) {
    return f.search && f.search->end && f.search->end->stopped == "interrupted";
}

} // namespace

void follow_folder(WorkbenchState& s, const std::string& given) {
    stop_following(s);
    const std::string dir = std::filesystem::absolute(given).lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
        s.follow.error = fmt::format("{}: no such folder", dir);
        add_log(s, "error: " + s.follow.error);
        return;
    }
    s.follow.dir = dir;
    s.follow.typed = dir;
    s.follow.error.clear();
    s.cluster.reveal = true;
    add_log(s, fmt::format("following {}", dir));
}

void stop_following(WorkbenchState& s) {
    FolderFollow& f = s.follow;
    if (f.reading.valid()) f.retired.push_back(std::move(f.reading));
    f = FolderFollow{.typed = std::move(f.typed), .retired = std::move(f.retired)};
}

void poll_followed_folder(FolderFollow& f, double now_s) {
    std::erase_if(f.retired, [](const std::future<FollowRead>& r) { return ready(r); });
    if (f.dir.empty()) return;
    if (f.reading.valid()) {
        if (!ready(f.reading)) return;
        try {
            FollowRead r = f.reading.get();
            if (r.search) f.search = std::move(r.search);
            f.scene_toml = r.scene_toml;
            f.error.clear();
        } catch (const std::exception& e) {
            f.error = e.what(); // shown; the next read may find it whole
        }
        f.next_read_s = now_s + (interrupted(f) ? kInterruptedReadInterval_s : kReadInterval_s);
    }
    // An end reads the folder no more, but an interrupted one: a resumed run may continue.
    if ((followed_search_ended(f) && !interrupted(f)) || now_s < f.next_read_s) return;
    f.reading = std::async(std::launch::async, read, f.dir, f.search);
}

bool followed_search_ended(const FolderFollow& f) {
    return f.search && f.search->end.has_value();
}

SearchProgress followed_progress(const FollowedSearch& f) {
    SearchProgress p;
    p.running = !f.end;
    p.method = f.method;
    p.names = f.names;
    p.bounds = f.bounds;
    p.history = f.rows.candidates;
    p.stages = f.rows.stages;
    if (f.end) p.result = followed_result(f);
    p.out_dir = f.dir;
    return p;
}

} // namespace fird::ui
