// A picture against its golden image (tests/*/golden), with the tolerance every golden test
// states: a pixel differs when a channel is more than 16 counts off (anti-aliased edges and
// the driver's rounding move single pixels by less); at most 0.5 % of the pixels may
// differ, and the mean absolute difference over all channels stays under 1.5 counts (a
// shifted label or a changed colour map moves far more). On failure a diff image (differing
// pixels in red) is written to the test's temporary folder and named on stderr.
//
// FIRD_UPDATE_GOLDENS=1 writes the golden from the picture instead (scripts/update_goldens.sh).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fird::test {

void expect_like_golden(const std::vector<std::uint8_t>& rgba, int w, int h,
                        const std::string& golden_path);

} // namespace fird::test
