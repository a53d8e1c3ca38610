// The vector width a CPU Vulkan driver (lavapipe) compiles shaders for, and where it keeps
// them: the CPU's widest for a process that only computes.
#pragma once

namespace fird::vk {

// What a process asks of the device: compute passes only, or drawing too (fragment
// shaders: the workbench, fird screenshot).
enum class DeviceWork { Compute, ComputeAndDraw };

// lavapipe (llvmpipe) compiles every shader for 256-bit vectors, 8 lanes, even on a CPU
// with AVX-512 (Mesa 22.3 keeps 256 "until 512 is known as correct and not slower"). A
// search's candidate costs 17-27 % less at 512 bits (16 lanes) on AMD Zen 5 (two runs,
// docs/benchmarks.md), every far field the same count for count. So where the CPU has AVX-512,
// LP_NATIVE_VECTOR_WIDTH is unset and the process only computes, this sets it to 512.
// A process that draws keeps Mesa's width: Mesa 22.3 crashes in LLVM compiling fragment
// shaders at 512 bits (require_fragment_shaders refuses it in one line).
//
// Wherever the width is set (here or by the user), the process's shader cache moves to a
// folder of that width's own, "lavapipe-512bit" in the folder Mesa would use
// (MESA_SHADER_CACHE_DIR, else the XDG cache home, else ~/.cache; off where none is known):
// lavapipe's on-disk cache keys a compiled shader without the width, so a shader compiled at
// one width would otherwise be found and run at another, which hid that crash until
// 2026-12-07 and could run a compute pass's code at lanes it was not compiled for.
//
// The user's LP_NATIVE_VECTOR_WIDTH always wins. GPU drivers read neither variable's width
// (their cache moves with it, harmlessly). llvmpipe reads the width once, when it first
// enumerates its device, and setenv is not safe beside a getenv on another thread: call
// this first thing in main, before any thread starts (MPI's own included).
void choose_cpu_driver_width(DeviceWork work);

} // namespace fird::vk
