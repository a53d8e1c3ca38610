// A picked ray: its identity is its index in the rayset (the same ray in a preview and in
// the full trace, alone or among others), and its recorded RQRM walk against answers
// found without it: a flat reflector's analytic descent and hit, the quadtree read back
// on its own, the transitions Algorithms 2-4 allow, and the hit the batch trace finds.
#include <cmath>
#include <cstdlib>

#include <glm/geometric.hpp>

#include "fastpath/picked_ray.hpp"
#include "fastpath/scene_params.hpp"
#include "io/scene_file.hpp"
#include "traced_scene.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

Scene scene_file(const char* name) {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/" + name);
}

// The first `count` indices of the scene's rayset whose rays meet the reflector (the
// fast path's own batch trace says so: t >= 0), with those hits.
struct Hitting {
    std::vector<std::uint64_t> indices;
    std::vector<glm::dvec4> hits; // point, t
};
Hitting hitting_rays(FastTracer& tracer, const Scene& s, std::size_t count) {
    const auto indices = sample_effective_ray_indices(s, std::uint32_t(4 * count));
    std::vector<Ray> rays;
    for (const std::uint64_t i : indices)
        rays.push_back(effective_ray(s, i));
    std::vector<glm::dvec4> hits;
    (void)tracer.run_rays(rays, &hits);
    Hitting h;
    for (std::size_t k = 0; k < indices.size() && h.indices.size() < count; ++k)
        if (hits[k].w >= 0.0) h.indices.push_back(indices[k]), h.hits.push_back(hits[k]);
    return h;
}

using PickedRayTest = VulkanTest;

// The samplers keyed by (seed, index) alone give ray i whatever the count emitted; the
// stratified one also keys the stratum by the count, so a rayset is named by its count
// (TraceForViews::rayset_rays): a preview at fewer rays shows and picks the full trace's
// rays, under the same indices, with the same paths.
TEST_F(PickedRayTest, AnIndexIsTheSameRayInThePreviewTheFullTraceAndAlone) {
    const Scene s = scene_file("test/focused_paraboloid.toml");
    for (const SamplerKind sampler : {SamplerKind::Random, SamplerKind::Sobol})
        for (const std::uint64_t i : {0ull, 777ull, 99999ull}) {
            const Ray a = emit_ray(s.source, sampler, s.trace.seed, i, 100000);
            const Ray b = emit_ray(s.source, sampler, s.trace.seed, i, 10000000);
            EXPECT_EQ(a.origin, b.origin) << i;
            EXPECT_EQ(a.direction, b.direction) << i;
        }
    const std::uint64_t full = 100000;
    const auto preview =
        render::trace_for_views(ctx(), s, {.rays = 20000, .rayset_rays = full, .paths = 40});
    const auto traced = render::trace_for_views(ctx(), s, {.rays = full, .paths = 40});
    ASSERT_EQ(preview.viewport.paths.size(), traced.viewport.paths.size());
    for (std::size_t k = 0; k < traced.viewport.paths.size(); ++k) {
        const RayPath& p = preview.viewport.paths[k];
        const RayPath& q = traced.viewport.paths[k];
        EXPECT_EQ(p.ray_index, q.ray_index);
        // Same rays, same reflector, same pipeline: the same floats.
        EXPECT_EQ(p.vertices, q.vertices) << p.ray_index;
    }
    // Picked alone in the preview = the same index traced among 40 in the full trace. The
    // walk-recording pipeline is compiled on its own; its float results may differ by a
    // few ulps of the ~20 mm coordinates (2e-6 mm each): 1e-4 mm bounds that.
    for (const std::size_t k : {std::size_t(3), std::size_t(17), std::size_t(31)}) {
        const RayPath& among = traced.viewport.paths[k];
        const PickedRay alone = render::pick_ray(preview, among.ray_index);
        ASSERT_EQ(alone.path.vertices.size(), among.vertices.size()) << among.ray_index;
        for (std::size_t v = 0; v < among.vertices.size(); ++v)
            EXPECT_LT(glm::length(alone.path.vertices[v] - among.vertices[v]), 1e-4)
                << among.ray_index << " vertex " << v;
    }
    // Ray i as the CPU emits it is a ray the full trace's device rayset holds (generated
    // there in float: within 1e-5 of the double one; the nearest other direction of 1e5
    // isotropic rays is ~1e-2 away, so the match is that ray).
    Scene at_full = s;
    at_full.trace.rays = full;
    FastTracer tracer(ctx(), at_full, at_full.trace.seed);
    tracer.set_reflector(at_full.reflector);
    (void)tracer.run();
    const auto rayset = tracer.rayset();
    for (const std::size_t k : {std::size_t(0), std::size_t(20), std::size_t(39)}) {
        const Ray r = effective_ray(at_full, traced.viewport.paths[k].ray_index);
        double nearest = 1e9;
        for (const Ray& g : rayset)
            nearest = std::min(nearest, glm::length(g.direction - r.direction) +
                                            glm::length(g.origin - r.origin));
        EXPECT_LT(nearest, 1e-5) << traced.viewport.paths[k].ray_index;
    }
}

// A horizontal plane z = z0 under a point source above the holder: a ray falling on it
// enters the root (the whole holder) and meets the plane's height inside every node on
// its way down, so its walk is the root, then one descent per level, each to the node
// holding the hit point (texel q >> level) at t = (z0 - o.z) / d.z, then the hit there.
TEST_F(PickedRayTest, AFlatReflectorsWalkDescendsLevelByLevelToTheAnalyticHit) {
    Scene s = scene_file("test/flat_mirror.toml");
    s.reflector.parameters["sx"] = 0.0;
    s.reflector.parameters["sy"] = 0.0;
    const double z0 = s.reflector.parameters["z0"];
    FastTracer tracer(ctx(), s, s.trace.seed);
    tracer.set_reflector(s.reflector);
    const QuadtreeLayout q = quadtree_layout(s.trace.heightfield_w, s.trace.heightfield_h);
    const double tw = (s.holder.max_mm.x - s.holder.min_mm.x) / s.trace.heightfield_w;
    const double th = (s.holder.max_mm.y - s.holder.min_mm.y) / s.trace.heightfield_h;
    int checked = 0;
    for (const std::uint64_t i : sample_effective_ray_indices(s, 400)) {
        const Ray r = effective_ray(s, i);
        if (r.direction.z > -0.2) continue; // not a ray falling onto the plane
        const double t_hit = (z0 - r.origin.z) / r.direction.z;
        const glm::dvec3 p = r.origin + t_hit * r.direction;
        const double u = (p.x - s.holder.min_mm.x) / tw, v = (p.y - s.holder.min_mm.y) / th;
        if (u < 0 || v < 0 || u >= s.trace.heightfield_w || v >= s.trace.heightfield_h) continue;
        // Away from texel edges (0.1 texel): the node holding the hit is unambiguous in
        // float (the hit point's float error is ~1e-5 texel).
        if (std::abs(u - std::round(u)) < 0.1 || std::abs(v - std::round(v)) < 0.1) continue;
        const PickedRay picked = trace_picked_ray(tracer, s, i);
        SCOPED_TRACE(testing::Message() << "ray " << i);
        std::vector<WalkStep> walk;
        for (const WalkStep& w : picked.walk)
            if (w.bounce == 0) walk.push_back(w);
        ASSERT_EQ(walk.size(), q.levels);
        for (std::size_t k = 0; k < walk.size(); ++k) {
            const WalkStep& w = walk[k];
            const std::uint32_t level = q.levels - 1 - std::uint32_t(k);
            EXPECT_EQ(w.level, level);
            EXPECT_EQ(w.x, std::uint32_t(u) >> level);
            EXPECT_EQ(w.y, std::uint32_t(v) >> level);
            // Every node's max is the plane's height, lifted by the refined quadtree's
            // margin above float rounding (maxmip.comp: 1e-5 (|h| + 1) in the device's
            // frame, 2e-5 mm here): 1e-4 mm.
            EXPECT_NEAR(w.max_height_mm, z0, 1e-4);
            // Past the root's step the ray is at the plane: t_hit in float, to 1e-4 mm
            // (a few ulps of t ~ 10 mm, through the descent's (h - o.z) / d.z).
            if (k > 0) {
                EXPECT_NEAR(w.t, t_hit, 1e-4);
            }
            EXPECT_EQ(w.decision, k + 1 < walk.size() ? WalkDecision::Descend : WalkDecision::Hit);
        }
        EXPECT_NEAR(walk.back().t_next, t_hit, 1e-4);
        EXPECT_NEAR(glm::length(picked.path.vertices[1] - p), 0.0, 1e-4);
        if (++checked == 5) break;
    }
    EXPECT_EQ(checked, 5);
}

// Every recorded step of rays of Model C (six bounces, a fluted cup: advances and ascents
// between descents), in the paper's hit mode, against answers found without the walk:
// the node's max height is the quadtree read back on its own; the ray's height at t is the
// ray's own (bounce 0); each decision's next step is the one Algorithms 2-4 allow; a hit
// is the last step of its bounce, in the texel and at the t the batch trace found.
TEST_F(PickedRayTest, WalkStepsFollowAlgorithms2To4AndEndAtTheBatchTracesHit) {
    Scene s = scene_file("model_c.toml");
    s.trace.hit_mode = HitMode::Paper;
    s.trace.rays = 100000;
    FastTracer tracer(ctx(), s, s.trace.seed);
    tracer.set_reflector(s.reflector);
    const std::vector<float> tree = tracer.read_quadtree();
    const QuadtreeLayout q = quadtree_layout(s.trace.heightfield_w, s.trace.heightfield_h);
    const Hitting hitting = hitting_rays(tracer, s, 8);
    ASSERT_EQ(hitting.indices.size(), 8u);
    std::size_t advances = 0, ascents = 0;
    for (std::size_t n = 0; n < hitting.indices.size(); ++n) {
        const PickedRay picked = trace_picked_ray(tracer, s, hitting.indices[n]);
        SCOPED_TRACE(testing::Message() << "ray " << picked.index);
        const auto& walk = picked.walk;
        ASSERT_FALSE(walk.empty());
        for (std::size_t k = 0; k < walk.size(); ++k) {
            const WalkStep& w = walk[k];
            SCOPED_TRACE(testing::Message() << "step " << k << ": " << describe_walk_step(w));
            ASSERT_LT(w.level, q.levels);
            ASSERT_LT(w.x, q.w[w.level]);
            ASSERT_LT(w.y, q.h[w.level]);
            EXPECT_EQ(w.max_height_mm,
                      tree[q.offset[w.level] + std::size_t(w.y) * q.w[w.level] + w.x]);
            if (w.bounce == 0) { // float t on a ~10 mm path: 1e-4 mm
                EXPECT_NEAR(w.ray_z_mm, picked.ray.origin.z + w.t * picked.ray.direction.z, 1e-4);
            }
            const bool last_of_bounce = k + 1 == walk.size() || walk[k + 1].bounce != w.bounce;
            const bool below = std::min(w.ray_z_mm, w.ray_z_exit_mm) <= w.max_height_mm;
            switch (w.decision) {
            case WalkDecision::Descend:
                EXPECT_TRUE(below);
                ASSERT_FALSE(last_of_bounce);
                EXPECT_EQ(walk[k + 1].level + 1, w.level);
                EXPECT_EQ(walk[k + 1].x >> 1, w.x); // a child of this node
                EXPECT_EQ(walk[k + 1].y >> 1, w.y);
                break;
            case WalkDecision::Advance:
            case WalkDecision::Ascend: {
                ASSERT_FALSE(last_of_bounce);
                const WalkStep& next = walk[k + 1];
                const bool up = w.decision == WalkDecision::Ascend;
                EXPECT_EQ(next.level, w.level + (up ? 1 : 0));
                // The neighbour across the face it left through, at this step's level:
                // a sibling (advance) or in another parent (ascend: the next step is
                // that parent).
                const auto dx = std::abs(double(next.x << (up ? 1 : 0)) - double(w.x));
                const auto dy = std::abs(double(next.y << (up ? 1 : 0)) - double(w.y));
                EXPECT_LE(dx, up ? 2.0 : 1.0);
                EXPECT_LE(dy, up ? 2.0 : 1.0);
                const bool same_parent = up ? next.x == w.x >> 1 && next.y == w.y >> 1
                                            : next.x >> 1 == w.x >> 1 && next.y >> 1 == w.y >> 1;
                EXPECT_EQ(same_parent, !up);
                EXPECT_FLOAT_EQ(next.t, w.t_exit);
                (up ? ascents : advances) += 1;
                break;
            }
            case WalkDecision::Hit:
            case WalkDecision::Leave:
                EXPECT_TRUE(last_of_bounce);
                break;
            case WalkDecision::NoRoot:
            case WalkDecision::OwnTexel:
                EXPECT_EQ(w.level, 0u);
                ASSERT_FALSE(last_of_bounce);
                EXPECT_EQ(walk[k + 1].x, w.x); // crossed from the same texel
                break;
            case WalkDecision::Undecided:
                ADD_FAILURE() << "the walk hit its step limit";
            }
        }
        // The first bounce's hit is the batch trace's (same rays, the same float t up to
        // the separately compiled pipeline's ulps: 1e-4 mm), in the texel under it.
        const WalkStep* hit = nullptr;
        for (const WalkStep& w : walk)
            if (w.bounce == 0 && w.decision == WalkDecision::Hit) hit = &w;
        ASSERT_NE(hit, nullptr);
        EXPECT_NEAR(hit->t_next, hitting.hits[n].w, 1e-4);
        const double tw = (s.holder.max_mm.x - s.holder.min_mm.x) / s.trace.heightfield_w;
        const double th = (s.holder.max_mm.y - s.holder.min_mm.y) / s.trace.heightfield_h;
        // The hit point lies in that texel, or on its edge within float rounding (the
        // paper mode's hit is often where the ray enters the texel): 1e-3 texel.
        const double u = (hitting.hits[n].x - s.holder.min_mm.x) / tw;
        const double v = (hitting.hits[n].y - s.holder.min_mm.y) / th;
        EXPECT_GE(u, hit->x - 1e-3);
        EXPECT_LE(u, hit->x + 1 + 1e-3);
        EXPECT_GE(v, hit->y - 1e-3);
        EXPECT_LE(v, hit->y + 1 + 1e-3);
        // The path's bounces are the walk's: one walk per reflection, plus the last, which
        // is empty only where the last reflection left from the reflector's highest point
        // on a rising ray (the paper mode lifts a hit onto its texel's top, and a rising
        // ray from the top has no node to visit).
        const auto walks =
            std::min<std::uint32_t>(picked.path.reflections + 1, s.trace.max_bounces);
        if (walk.back().bounce + 1 != walks) {
            EXPECT_EQ(walk.back().bounce + 2, walks);
            ASSERT_GT(picked.path.reflections, 0u);
            // The texel of the last reflection: its walk's hit (a paper hit often lies on
            // a texel's edge, so not the hit point's floor).
            const WalkStep* last_hit = nullptr;
            for (const WalkStep& w : walk)
                if (w.bounce + 1 == picked.path.reflections && w.decision == WalkDecision::Hit)
                    last_hit = &w;
            ASSERT_NE(last_hit, nullptr);
            ASSERT_EQ(last_hit->level, 0u);
            EXPECT_EQ(tree[q.offset[0] + std::size_t(last_hit->y) * q.w[0] + last_hit->x],
                      tree[q.offset[q.levels - 1]]);
            EXPECT_GT(picked.path.direction.z, 0.0);
        }
    }
    EXPECT_GT(advances, 0u); // the check above saw both kinds of moves
    EXPECT_GT(ascents, 0u);
}

// An index past the rayset, or of a ray the holder discards, is a one-line error naming it.
TEST_F(PickedRayTest, ABadIndexIsAOneLineErrorNamingIt) {
    const Scene s = scene_file("test/flat_mirror.toml");
    try {
        (void)effective_ray(s, s.trace.rays);
        ADD_FAILURE() << "no error past the rayset";
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(std::to_string(s.trace.rays)), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    std::uint64_t discarded = 0; // an upward ray of the source above the holder
    while (ray_meets_box(emit_ray(s.source, s.trace.sampler, s.trace.seed, discarded, s.trace.rays),
                         s.holder))
        ++discarded;
    try {
        (void)effective_ray(s, discarded);
        ADD_FAILURE() << "no error for discarded ray " << discarded;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("discarded"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace fird::test
