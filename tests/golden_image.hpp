// A picture against its golden image (tests/*/golden), with the tolerance every golden test
// states: a pixel differs when a channel is more than 16 counts off (anti-aliased edges and
// the driver's rounding move single pixels by less); at most 0.5 % of the pixels may
// differ, and the mean absolute difference over all channels stays under 1.5 counts (a
// shifted label or a changed colour map moves far more). On failure a diff image (differing
// pixels in red) is written to the test's temporary folder and named on stderr.
//
// A picture rasterized by the device (Drawn::OnDevice: the viewport, the workbench frame)
// may place an edge or a line a pixel away from the golden's: Vulkan lets conformant
// rasterizers differ there (coverage at sub-pixel precision, non-strict lines; lavapipe
// against NVIDIA's driver, 2026-12-04: 337 of the viewport's 64000 pixels differed in
// place, none a pixel away). Such a picture's pixel differs only when it matches no golden
// pixel within one pixel, or the golden's pixel matches none of the picture's: both ways,
// so content missing from either side still counts. A picture drawn on the host (cairo:
// the far-field pictures, the plots) is the same on every device and compared in place.
//
// FIRD_UPDATE_GOLDENS=1 writes the golden from the picture instead (scripts/update_goldens.sh).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fird::test {

enum class Drawn { OnHost, OnDevice };

void expect_like_golden(const std::vector<std::uint8_t>& rgba, int w, int h,
                        const std::string& golden_path, Drawn drawn);

} // namespace fird::test
