// A chart drawn with ImGui's draw lists (ui/chart_widget.hpp) at sizes past what one piece
// of a 16-bit-indexed draw list holds: a stage's best-so-far line of a long search (a point
// per candidate) and a dot per candidate. ImGui splits a window's list at 65,536 vertices
// only between primitives; one primitive past the bound wraps its 16-bit indices (wrong
// triangles, its last vertices never drawn), which a line of 100,000 points did before the
// chart gave it in pieces.
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>
#include <imgui.h>

#include "chart_widget.hpp"
#include "plot/chart.hpp"

namespace fird::ui {
namespace {

TEST(ChartWidget, AHundredThousandPointLineAndDotsDrawPastSixteenBitIndices) {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(1200, 800);
    io.DeltaTime = 1.0f / 60.0f;
    io.IniFilename = nullptr;
    // As the workbench's renderer declares (it draws each command at its VtxOffset).
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);

    constexpr std::size_t n = 100000;
    plot::Chart chart;
    plot::Series line{.kind = plot::Series::Kind::Line, .label = "best so far"};
    plot::Series dots{.kind = plot::Series::Kind::Points, .label = "candidates"};
    for (std::size_t i = 0; i < n; ++i) {
        // A zigzag, so that no segment is dropped as collinear or degenerate.
        line.x.push_back(double(i));
        line.y.push_back(1.0 + 0.5 * double(i % 2));
        if (i % 10 == 0) {
            dots.x.push_back(double(i));
            dots.y.push_back(1.25);
        }
    }
    chart.series = {line, dots};

    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(io.DisplaySize);
    ImGui::Begin("chart");
    chart_widget("progress", chart, ImVec2(1100, 700));
    ImGui::End();
    ImGui::Render();

    const ImDrawData* dd = ImGui::GetDrawData();
    ASSERT_NE(dd, nullptr);
    // Past the bound: more vertices than one 16-bit-indexed piece holds, and every vertex
    // drawn: a command's indices (16-bit, from its VtxOffset) reach each vertex of the list.
    // One primitive past the bound wraps its indices (ImGui counts them in 16 bits), drawing
    // wrong triangles and leaving its last vertices unreached.
    EXPECT_GT(dd->TotalVtxCount, 1 << 16);
    for (int l = 0; l < dd->CmdListsCount; ++l) {
        const ImDrawList* list = dd->CmdLists[l];
        std::vector<bool> reached(std::size_t(list->VtxBuffer.Size), false);
        for (const ImDrawCmd& cmd : list->CmdBuffer)
            for (unsigned k = 0; k < cmd.ElemCount; ++k) {
                const std::size_t vertex =
                    std::size_t(cmd.VtxOffset) + list->IdxBuffer[int(cmd.IdxOffset + k)];
                ASSERT_LT(vertex, reached.size()) << "list " << l;
                reached[vertex] = true;
            }
        std::size_t unreached = 0;
        for (bool r : reached)
            unreached += r ? 0 : 1;
        EXPECT_EQ(unreached, 0u) << "list " << l << " of " << reached.size() << " vertices";
    }
    ImGui::DestroyContext();
}

} // namespace
} // namespace fird::ui
