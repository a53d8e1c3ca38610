// The vector width a CPU Vulkan driver (lavapipe) compiles shaders for: the CPU's widest.
#pragma once

namespace fird::vk {

// lavapipe (llvmpipe) compiles every shader for 256-bit vectors, 8 lanes, even on a CPU
// with AVX-512 (Mesa 22.3 keeps 256 "until 512 is known as correct and not slower").
// A search's candidate costs 8-25 % less at 512 bits (16 lanes) on AMD Zen 5, with every
// far field the same count for count (docs/benchmarks.md), so where the CPU has AVX-512
// and LP_NATIVE_VECTOR_WIDTH is unset, this sets it to 512 for this process.
// The user's own setting always wins (LP_NATIVE_VECTOR_WIDTH=256 gives Mesa's default
// back). GPU drivers never read the variable. llvmpipe reads it once, when it first
// enumerates its device, so this must run before the process's first vkCreateInstance
// (Context::create calls it); and since setenv is not safe beside a getenv on another
// thread, a program calls it first thing in main, before it starts threads (MPI's too).
void ask_cpu_driver_for_native_lanes();

} // namespace fird::vk
