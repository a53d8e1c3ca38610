#version 450
// Exclusive prefix sum of the rayset-order bucket counts, in place, by one workgroup:
// each invocation sums a run of buckets, the run totals are scanned in shared memory,
// then each invocation writes its run's offsets.
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = FIRD_BUCKET_SCAN_WORKGROUP_SIZE) in;
layout(std430, binding = kScanBindBuckets) buffer Buckets { uint buckets[]; };

const uint kRun = kRaysetOrderBuckets / FIRD_BUCKET_SCAN_WORKGROUP_SIZE;
shared uint run_total[FIRD_BUCKET_SCAN_WORKGROUP_SIZE];

void main() {
    const uint id = gl_LocalInvocationID.x;
    const uint first = id * kRun;
    uint sum = 0u;
    for (uint k = 0u; k < kRun; ++k) sum += buckets[first + k];
    run_total[id] = sum;
    barrier();
    // Hillis-Steele inclusive scan of the run totals.
    for (uint stride = 1u; stride < FIRD_BUCKET_SCAN_WORKGROUP_SIZE; stride <<= 1u) {
        const uint add = id >= stride ? run_total[id - stride] : 0u;
        barrier();
        run_total[id] += add;
        barrier();
    }
    uint offset = run_total[id] - sum;
    for (uint k = 0u; k < kRun; ++k) {
        const uint n = buckets[first + k];
        buckets[first + k] = offset;
        offset += n;
    }
}
