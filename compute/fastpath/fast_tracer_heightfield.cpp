// The height-field passes: the family's heights (or the mesh's raster), the max-mip
// quadtrees (paper §4) and the level the walk starts at.
#include "fast_tracer.hpp"

#include <chrono>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

namespace fird {

using namespace fast_tracer_detail;

double FastTracer::rasterize_mesh() {
    if (!state().heightfield_dirty || !mesh_) return 0.0;
    // The paper's z-buffer step for meshes (its own submissions, once per mesh).
    const auto t0 = std::chrono::steady_clock::now();
    mesh_rasterizer_->rasterize(*mesh_, origin_, scene_.holder, params_.hf_w, params_.hf_h,
                                state().paper_tree, state().gradients);
    // The texel corners are the centres of a grid one texel larger, half a texel out.
    const double half_x = (scene_.holder.max_mm.x - scene_.holder.min_mm.x) / params_.hf_w / 2;
    const double half_y = (scene_.holder.max_mm.y - scene_.holder.min_mm.y) / params_.hf_h / 2;
    const Holder around{scene_.holder.min_mm - glm::dvec3(half_x, half_y, 0.0),
                        scene_.holder.max_mm + glm::dvec3(half_x, half_y, 0.0)};
    const vk::Buffer corner_gradients(
        *ctx_, std::uint64_t(params_.hf_w + 1) * (params_.hf_h + 1) * 8, vk::kStorageUsage,
        vk::MemoryUse::Device, "fird.mesh_raster.corner_gradients");
    mesh_rasterizer_->rasterize(*mesh_, origin_, around, params_.hf_w + 1, params_.hf_h + 1,
                                state().corners, corner_gradients);
    return ms_since(t0);
}

bool FastTracer::trace_reads_paper_tree() const {
    // A mesh's gradients are its faces' (the raster's), read in both hit modes.
    return params_.hit_mode == gpu::kHitModePaper || mesh_;
}

void FastTracer::record_heightfield(VkCommandBuffer cb, FastRun& run, bool with_paper) {
    // A search's candidates (the refined mode, an analytic family) skip the paper's
    // products: half the stores and the family evaluated at the corners alone.
    const bool paper = with_paper || trace_reads_paper_tree();
    timed(cb, &run.timings.heightfield_ms, nullptr, [&] {
        constexpr std::uint32_t g = FIRD_HEIGHTFIELD_WORKGROUP_SIZE;
        if (!mesh_) {
            const passes::HeightfieldBindings hf{.params = vk::uniform(state().params_buffer),
                                                 .heights = vk::storage(state().paper_tree),
                                                 .gradients = vk::storage(state().gradients),
                                                 .control =
                                                     vk::storage_texel(state().control.texels),
                                                 .corners = vk::storage(state().corners)};
            (paper ? heightfield_pipeline_ : heightfield_refined_pipeline_)
                .dispatch(cb, hf, {}, groups(params_.hf_w + 1, g), groups(params_.hf_h + 1, g));
            vk::barrier_all(cb);
        }
        const passes::MaxMipBindings mm{.params = vk::uniform(state().params_buffer),
                                        .paper = vk::storage(state().paper_tree),
                                        .refined = vk::storage(state().refined_tree),
                                        .corners = vk::storage_texel(state().corners_view),
                                        .paper_in = vk::storage_texel(state().paper_view),
                                        .refined_in = vk::storage_texel(state().refined_view)};
        for (std::uint32_t level = 0; level < params_.levels; ++level) {
            const gpu::MaxMipPush push{.level = level};
            (level == 0 ? maxmip_level0_pipeline_
             : paper    ? maxmip_pipeline_
                        : maxmip_refined_pipeline_)
                .dispatch(cb, mm, push, groups(params_.level_w[level], g),
                          groups(params_.level_h[level], g));
            vk::barrier_all(cb);
        }
        const passes::WalkStartBindings ws{
            .params = vk::uniform(state().params_buffer),
            .pyramid = vk::storage(params_.hit_mode == gpu::kHitModePaper ? state().paper_tree
                                                                          : state().refined_tree),
            .level = vk::storage(state().walk_start)};
        walk_start_pipeline_.dispatch(cb, ws, {}, 1);
    });
    vk::barrier_all(cb);
    state().paper_tree_stale = !paper;
}

void FastTracer::build_paper_heightfield() {
    if (!current_.reflector) throw std::logic_error("FastTracer: no reflector set");
    if (!current_.heightfield_dirty && !current_.paper_tree_stale) return;
    FastRun unused;
    unused.timings.heightfield_ms += rasterize_mesh();
    submit(&unused.timings.heightfield_ms,
           [&](VkCommandBuffer cb) { record_heightfield(cb, unused, true); });
    current_.heightfield_dirty = false;
}

std::vector<float> FastTracer::read_quadtree() {
    build_paper_heightfield();
    const QuadtreeLayout q = quadtree_layout(params_.hf_w, params_.hf_h);
    std::vector<float> tree = state().paper_tree.download_as<float>(*ctx_, q.total_floats);
    for (float& h : tree)
        h = float(double(h) + origin_.z); // out of the frame
    return tree;
}

std::vector<glm::vec2> FastTracer::read_gradients() {
    build_paper_heightfield();
    return state().gradients.download_as<glm::vec2>(*ctx_,
                                                    std::size_t(params_.hf_w) * params_.hf_h);
}

} // namespace fird
