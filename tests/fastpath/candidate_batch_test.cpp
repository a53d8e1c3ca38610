// Several candidates per submission (Evaluator::evaluate_batch, issue 24 item 3) against
// the same candidates evaluated one at a time: the same rays through the same passes, so
// every count, every bounce's rays and every l2 must be equal, not merely close.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "evaluation/evaluator.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "io/scene_file.hpp"
#include "reduction_bound.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

Scene small_scene(const std::string& name) {
    Scene s = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/" + name);
    s.trace.rays = 20000;
    s.trace.heightfield_w = 192;
    s.trace.heightfield_h = 128;
    s.trace.farfield_w = 180;
    s.trace.farfield_h = 90;
    return s;
}

// `count` reflectors of the scene's family: each moves one parameter by a few percent (in
// turn), and the last repeats the first (a height field a batch slot may still hold).
std::vector<ReflectorDesc> candidates(const Scene& s, std::size_t count) {
    std::vector<ReflectorDesc> out;
    std::vector<std::string> names;
    for (const auto& [name, value] : s.reflector.parameters)
        names.push_back(name);
    for (std::size_t i = 0; i + 1 < count; ++i) {
        ReflectorDesc r = s.reflector;
        double& v = r.parameters[names[i % names.size()]];
        v += (v == 0.0 ? 0.1 : 0.03 * v) * double(1 + i / names.size());
        out.push_back(r);
    }
    out.push_back(out.front());
    return out;
}

void expect_same(const CandidateResult& batch, const CandidateResult& single) {
    const RayTally& b = batch.run.tally;
    const RayTally& s = single.run.tally;
    EXPECT_EQ(b.emitted, s.emitted);
    EXPECT_EQ(b.discarded, s.discarded);
    EXPECT_EQ(b.direct, s.direct);
    EXPECT_EQ(b.farfield, s.farfield);
    EXPECT_EQ(b.lost, s.lost);
    EXPECT_EQ(b.below_surface, s.below_surface);
    EXPECT_EQ(b.by_reflections, s.by_reflections);
    EXPECT_EQ(batch.run.aborted, single.run.aborted);
    ASSERT_EQ(batch.run.bounces.size(), single.run.bounces.size());
    for (std::size_t k = 0; k < batch.run.bounces.size(); ++k)
        EXPECT_EQ(batch.run.bounces[k].rays, single.run.bounces[k].rays) << "bounce " << k;
    // The same far field reduced by the same passes in the same order: the same float.
    ASSERT_TRUE(batch.l2_lm.has_value());
    EXPECT_EQ(*batch.l2_lm, *single.l2_lm);
    EXPECT_EQ(batch.farfield_lm, single.farfield_lm);
}

// The desired far field: the scene's own reflector with other rays (any far field will do;
// the l2s are compared, not judged).
FarField desired(const vk::Context& ctx, const Scene& s) {
    Fidelity f = scene_fidelity(s);
    f.seed = 99;
    Evaluator e(ctx, s, f);
    (void)e.evaluate(s.reflector);
    return e.farfield();
}

// Each candidate evaluated alone (one submission each), against `want`.
std::vector<CandidateResult> one_at_a_time(Evaluator& e, const FarField& want,
                                           const std::vector<ReflectorDesc>& list) {
    e.set_desired(want);
    std::vector<CandidateResult> out;
    for (const ReflectorDesc& r : list)
        out.push_back(e.evaluate(r));
    return out;
}

// 18 candidates: 16 in one submission (FastTracer::kMaxBatchCandidates), 2 in a second,
// on each model (a cylinder's and spheres' rays, born ordered by the stratified sampler),
// and on Model A's independent rays (sorted).
TEST_F(VulkanTest, ABatchOfCandidatesEqualsSingleEvaluationsCountForCount) {
    for (const auto& [name, sampler] : {std::pair{"model_a.toml", SamplerKind::Stratified},
                                        std::pair{"model_a.toml", SamplerKind::Random},
                                        std::pair{"model_b.toml", SamplerKind::Stratified},
                                        std::pair{"model_c.toml", SamplerKind::Stratified}}) {
        SCOPED_TRACE(fmt::format("{}, {}", name, sampler_name(sampler)));
        Scene s = small_scene(name);
        s.trace.sampler = sampler;
        const std::vector<ReflectorDesc> list = candidates(s, 18);
        const FarField want = desired(ctx(), s);
        Evaluator single(ctx(), s, scene_fidelity(s));
        const std::vector<CandidateResult> singles = one_at_a_time(single, want, list);

        Evaluator batched(ctx(), s, scene_fidelity(s));
        batched.set_desired(want);
        (void)batched.evaluate(list.back()); // the rayset, kept for the batch
        const std::uint64_t before = ctx().submissions();
        const std::vector<CandidateResult> batch = batched.evaluate_batch(list);
        EXPECT_EQ(ctx().submissions() - before, 2u);
        ASSERT_EQ(batch.size(), list.size());
        for (std::size_t k = 0; k < list.size(); ++k) {
            SCOPED_TRACE(fmt::format("candidate {}", k));
            expect_same(batch[k], singles[k]);
        }
        // The last candidate's far field is the evaluator's, as after evaluate().
        EXPECT_EQ(batched.farfield().lm, single.farfield().lm);
        // The same list again: slots 1 to 14 still hold candidates 1 to 14 (slot 0 took
        // candidate 16 in the second submission, the evaluator's own state 17), so their
        // height fields are not rebuilt (only the clears separate one candidate's readback
        // from the next's), and the results are the same.
        const std::vector<CandidateResult> kept = batched.evaluate_batch(list);
        for (std::size_t k = 0; k + 1 < list.size(); ++k) {
            SCOPED_TRACE(fmt::format("candidate {} again", k));
            if (k >= 1 && k <= 14) {
                EXPECT_TRUE(kept[k].run.heightfield_reused);
            }
            expect_same(kept[k], singles[k]);
        }
        // The repeat of candidate 0 in the second submission: a slot's height field, kept
        // or rebuilt, traces the same.
        EXPECT_EQ(*batch.back().l2_lm, *batch.front().l2_lm);
        // A batch without a rayset yet generates it with its first candidate.
        Evaluator fresh(ctx(), s, scene_fidelity(s));
        fresh.set_desired(want);
        const std::vector<CandidateResult> cold = fresh.evaluate_batch(list);
        for (std::size_t k = 0; k < list.size(); ++k)
            expect_same(cold[k], singles[k]);
    }
}

// [optimize] metric = "candela_l2": the device compares intensities weighted by solid
// angle, in a batch's submission as in compare(); each equals the CPU's farfield_distance
// of the read-back far fields (double) within float rounding's bound (reduction_bound.hpp:
// the far fields are the same floats on both sides, each term then carries the
// difference's, the square's, the weight's, the product's and its first addition's
// roundings), and the desired norm is that metric's.
TEST_F(VulkanTest, TheCandelaMetricOnTheDeviceIsTheCpuMetricOfTheSameFarFields) {
    Scene s = small_scene("model_a.toml");
    s.optimize.metric = FarFieldMetric::CandelaL2;
    const std::vector<ReflectorDesc> list = candidates(s, 3);
    const FarField want = desired(ctx(), s);
    Evaluator e(ctx(), s, scene_fidelity(s));
    e.set_desired(want);
    EXPECT_EQ(e.metric(), FarFieldMetric::CandelaL2);
    const FarField zero{want.width, want.height, std::vector<double>(want.lm.size(), 0.0)};
    FarField want_float = want;
    for (double& v : want_float.lm)
        v = double(float(v));
    EXPECT_NEAR(e.desired_norm_lm(), farfield_distance(want_float, zero, FarFieldMetric::CandelaL2),
                1e-9);
    const std::vector<CandidateResult> batch = e.evaluate_batch(list);
    const double last = farfield_distance(e.farfield(), want_float, FarFieldMetric::CandelaL2);
    const double bound =
        reduction_relative_bound(want.lm.size(), 5, true, ctx().limits().subgroup_size);
    EXPECT_NEAR(*batch.back().l2_lm, last, bound * last);
    EXPECT_NEAR(e.compare(), last, bound * last);
    // Not the lumen metric: on Model A the two differ by far more than rounding.
    const double lumens = farfield_distance(e.farfield(), want_float, FarFieldMetric::L2);
    EXPECT_GT(std::abs(last - lumens), 0.1 * lumens);
}

// Where the device memory budget (--max-device-memory) leaves room for three candidates'
// height fields and far fields, a batch takes three quarters of it (two extra states, the
// third candidate in the evaluator's own), so it splits into submissions of three, with
// the same results; nothing fails for want of memory.
TEST_F(VulkanTest, ABatchSplitsWhereMemoryHoldsFewerCandidates) {
    const Scene s = small_scene("model_a.toml");
    const std::vector<ReflectorDesc> list = candidates(s, 10);
    const FarField want = desired(ctx(), s);
    Evaluator single(ctx(), s, scene_fidelity(s));
    const std::vector<CandidateResult> singles = one_at_a_time(single, want, list);

    // The budget: what one evaluator holds after its first evaluation, with the l2 slots
    // of ten candidates, plus three candidates' states and a fifth of one (three quarters:
    // 2.4 states, of which two are allocated; the rest is room for the buffers' alignment).
    const std::uint64_t state_bytes = reflector_state_bytes(scene_params(s, s.trace.seed));
    std::uint64_t in_use = 0;
    {
        const vk::Context probe = vk::Context::create({.validation = true});
        Evaluator e(probe, s, scene_fidelity(s));
        e.set_desired(want);
        (void)e.evaluate(list.back());
        in_use = probe.device_memory_in_use();
    }
    const vk::Context ctx = vk::Context::create(
        {.validation = true, .max_device_memory_bytes = in_use + 10 * 256 + state_bytes * 16 / 5});
    Evaluator batched(ctx, s, scene_fidelity(s));
    batched.set_desired(want);
    (void)batched.evaluate(list.back());
    const std::uint64_t before = ctx.submissions();
    const std::vector<CandidateResult> batch = batched.evaluate_batch(list);
    EXPECT_EQ(ctx.submissions() - before, 4u) << "10 candidates, 3 a submission";
    ASSERT_EQ(batch.size(), list.size());
    for (std::size_t k = 0; k < list.size(); ++k) {
        SCOPED_TRACE(fmt::format("candidate {}", k));
        expect_same(batch[k], singles[k]);
    }
    EXPECT_EQ(ctx.validation_errors(), 0u);
}

} // namespace
} // namespace fird::test
