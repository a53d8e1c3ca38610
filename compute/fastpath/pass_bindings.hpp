// What each fast-path shader binds, by name: one struct per pass, its members placed at
// the shader's binding constants (fird_shared.h) by fields(), the table vk::TypedPass makes
// the pipeline's layout and every dispatch from.
#pragma once

#include <array>

#include "fird_shared.h"
#include "vk/typed_pass.hpp"

namespace fird::passes {

inline constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
inline constexpr VkDescriptorType kUniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
inline constexpr VkDescriptorType kTexel = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
inline constexpr VkDescriptorType kStorageTexel = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;

// rayset.comp: the source's rays into `rays`, the effective ones counted.
struct RaysetBindings {
    vk::Binding params, rays, counters, buckets, emitter_table;
    static constexpr auto fields() {
        using B = RaysetBindings;
        return std::array<vk::BindingField<B>, 5>{{
            {gpu::kBindParams, kUniform, &B::params},
            {gpu::kRaysetBindRays, kStorageTexel, &B::rays},
            {gpu::kRaysetBindCounters, kStorage, &B::counters},
            {gpu::kRaysetBindBuckets, kStorage, &B::buckets},
            {gpu::kRaysetBindEmitterTable, kStorageTexel, &B::emitter_table},
        }};
    }
};
using RaysetPass = vk::TypedPass<RaysetBindings, gpu::RaysetPush>;

// heightfield.comp: the family's heights, gradients and texel corners.
struct HeightfieldBindings {
    vk::Binding params, heights, gradients, control, corners;
    static constexpr auto fields() {
        using B = HeightfieldBindings;
        return std::array<vk::BindingField<B>, 5>{{
            {gpu::kBindParams, kUniform, &B::params},
            {gpu::kHeightfieldBindHeights, kStorage, &B::heights},
            {gpu::kHeightfieldBindGradients, kStorage, &B::gradients},
            {gpu::kHeightfieldBindControl, kStorageTexel, &B::control},
            {gpu::kHeightfieldBindCorners, kStorage, &B::corners},
        }};
    }
};
using HeightfieldPass = vk::TypedPass<HeightfieldBindings>;

// maxmip.comp: one level of the paper's and the refined max-mip quadtrees.
struct MaxMipBindings {
    vk::Binding params, paper, refined, corners, paper_in, refined_in;
    static constexpr auto fields() {
        using B = MaxMipBindings;
        return std::array<vk::BindingField<B>, 6>{{
            {gpu::kBindParams, kUniform, &B::params},
            {gpu::kMaxMipBindPaper, kStorage, &B::paper},
            {gpu::kMaxMipBindRefined, kStorage, &B::refined},
            {gpu::kMaxMipBindCorners, kStorageTexel, &B::corners},
            {gpu::kMaxMipBindPaperIn, kStorageTexel, &B::paper_in},
            {gpu::kMaxMipBindRefinedIn, kStorageTexel, &B::refined_in},
        }};
    }
};
using MaxMipPass = vk::TypedPass<MaxMipBindings, gpu::MaxMipPush>;

// walk_start.comp: the quadtree level the source's rays start their walk at.
struct WalkStartBindings {
    vk::Binding params, pyramid, level;
    static constexpr auto fields() {
        using B = WalkStartBindings;
        return std::array<vk::BindingField<B>, 3>{{
            {gpu::kBindParams, kUniform, &B::params},
            {gpu::kWalkStartBindPyramid, kStorage, &B::pyramid},
            {gpu::kWalkStartBindLevel, kStorage, &B::level},
        }};
    }
};
using WalkStartPass = vk::TypedPass<WalkStartBindings>;

// trace.comp: one bounce of the RQRM walk (the paper's Algorithms 2-4) for every ray.
struct TraceBindings {
    vk::Binding params, rays_in, rays_out, counters, pyramid, heights, gradients, farfield, hits,
        buckets, texel_hits, walk, profile, walk_start, control, loop;
    static constexpr auto fields() {
        using B = TraceBindings;
        return std::array<vk::BindingField<B>, 16>{{
            {gpu::kBindParams, kUniform, &B::params},
            {gpu::kTraceBindRaysIn, kStorageTexel, &B::rays_in},
            {gpu::kTraceBindRaysOut, kStorageTexel, &B::rays_out},
            {gpu::kTraceBindCounters, kStorage, &B::counters},
            {gpu::kTraceBindPyramid, kStorageTexel, &B::pyramid},
            {gpu::kTraceBindHeights, kStorageTexel, &B::heights},
            {gpu::kTraceBindGradients, kTexel, &B::gradients},
            {gpu::kTraceBindFarField, kStorage, &B::farfield},
            {gpu::kTraceBindHits, kStorage, &B::hits},
            {gpu::kTraceBindBuckets, kStorage, &B::buckets},
            {gpu::kTraceBindTexelHits, kStorage, &B::texel_hits},
            {gpu::kTraceBindWalk, kStorage, &B::walk},
            {gpu::kTraceBindProfile, kStorage, &B::profile},
            {gpu::kTraceBindWalkStart, kStorage, &B::walk_start},
            {gpu::kTraceBindControl, kStorageTexel, &B::control},
            {gpu::kTraceBindLoop, kStorage, &B::loop},
        }};
    }
};
using TracePass = vk::TypedPass<TraceBindings, gpu::TracePush>;

// counts_to_lm.comp: the far field's ray counts to lumens.
struct ToLmBindings {
    vk::Binding counts, lumens;
    static constexpr auto fields() {
        using B = ToLmBindings;
        return std::array<vk::BindingField<B>, 2>{{
            {gpu::kToLmBindCounts, kStorageTexel, &B::counts},
            {gpu::kToLmBindLumens, kStorage, &B::lumens},
        }};
    }
};
using ToLmPass = vk::TypedPass<ToLmBindings, gpu::ToLmPush>;

// rayset_order.comp: rays scattered into their direction bucket's range.
struct OrderBindings {
    vk::Binding params, rays_in, rays_out, buckets, loop;
    static constexpr auto fields() {
        using B = OrderBindings;
        return std::array<vk::BindingField<B>, 5>{{
            {gpu::kBindParams, kUniform, &B::params},
            {gpu::kOrderBindRaysIn, kStorageTexel, &B::rays_in},
            {gpu::kOrderBindRaysOut, kStorageTexel, &B::rays_out},
            {gpu::kOrderBindBuckets, kStorage, &B::buckets},
            {gpu::kOrderBindLoop, kStorage, &B::loop},
        }};
    }
};
using OrderPass = vk::TypedPass<OrderBindings, gpu::RaysetOrderPush>;

// bucket_scan.comp: the direction buckets' counts to offsets.
struct BucketScanBindings {
    vk::Binding buckets;
    static constexpr auto fields() {
        using B = BucketScanBindings;
        return std::array<vk::BindingField<B>, 1>{{{gpu::kScanBindBuckets, kStorage, &B::buckets}}};
    }
};
using BucketScanPass = vk::TypedPass<BucketScanBindings>;

// bounce_args.comp: the next bounce's (or ordering's) dispatch sized from the counters.
struct BounceArgsBindings {
    vk::Binding counters, loop;
    static constexpr auto fields() {
        using B = BounceArgsBindings;
        return std::array<vk::BindingField<B>, 2>{{
            {gpu::kBounceArgsBindCounters, kStorage, &B::counters},
            {gpu::kBounceArgsBindLoop, kStorage, &B::loop},
        }};
    }
};
using BounceArgsPass = vk::TypedPass<BounceArgsBindings, gpu::BounceArgsPush>;

} // namespace fird::passes
