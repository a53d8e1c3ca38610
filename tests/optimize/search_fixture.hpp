// What the search tests share: the test scenes, a search with a method and the hooks a
// test needs, and the comparison of a resumed search with the uninterrupted one.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "optimize/search.hpp"

namespace fird::test {

inline Scene scene(const std::string& name) {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/test/" + name);
}

// run_search with the scene's settings and `method` (one stage at the last ray count for
// every method but auto).
inline SearchOutcome search(const vk::Context& ctx, const Scene& s, SearchMethod method,
                            SearchControl* control = nullptr, std::vector<Candidate> replay = {},
                            CandidateCallback callback = {},
                            std::optional<DesiredFarField> desired = std::nullopt,
                            bool refine = false) {
    SearchRequest request{.settings = search_settings(s),
                          .control = control,
                          .replay = std::move(replay),
                          .on_candidate = std::move(callback),
                          .desired = std::move(desired)};
    request.settings.refine = refine;
    request.settings.method = method;
    if (method != SearchMethod::Auto) request.settings.rays = {request.settings.rays.back()};
    return run_search(ctx, s, request);
}

// A search resumed from the first `replayed` candidates of an interrupted one is the
// uninterrupted search, row for row, to its best, final l2 and reason to stop.
inline void expect_resumed_is_whole(const SearchResult& resumed, const SearchResult& whole,
                                    std::size_t replayed) {
    ASSERT_EQ(resumed.history.size(), whole.history.size());
    for (std::size_t i = 0; i < whole.history.size(); ++i) {
        EXPECT_EQ(resumed.history[i].x, whole.history[i].x) << i;
        EXPECT_EQ(resumed.history[i].l2_lm, whole.history[i].l2_lm) << i;
        EXPECT_EQ(resumed.history[i].replayed, i < replayed) << i;
    }
    EXPECT_EQ(resumed.best_parameters, whole.best_parameters);
    EXPECT_EQ(resumed.final_l2_lm, whole.final_l2_lm);
    EXPECT_EQ(resumed.stopped, whole.stopped);
}

} // namespace fird::test
