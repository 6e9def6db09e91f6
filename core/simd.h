// Run-time choice of the SIMD instruction set of the vectorised field
// kernels. Each kernel is compiled for every x86-64 target Highway offers
// (AVX3 = AVX-512, AVX2, SSE4, SSSE3, and EMU128, the portable baseline any
// x86-64 runs) and Highway's dynamic dispatch picks the best one this CPU
// has, unless it is limited here or with the environment variable
// LINKSCAPE_SIMD_TARGET=<name> (read at the first vectorised field).
#pragma once

#include <string>
#include <vector>

namespace linkscape::simd {

// The targets the kernels were compiled for that this CPU runs, best first,
// whatever limit_targets has set (e.g. "AVX3", "AVX2", "SSE4", "SSSE3", "EMU128").
std::vector<std::string> available_targets();

// The target the kernels use now.
std::string current_target();

// "1.0.3": the Highway library the kernels were built with.
std::string highway_version();

// Makes `name` (one of available_targets(), any case, or "baseline" for the
// last of them) the best target the kernels may use; "" lifts the limit.
// Throws std::invalid_argument naming the available targets for any other
// name. Call it while no field is being computed (the choice is
// process-wide).
void limit_targets(const std::string& name);

// Applies LINKSCAPE_SIMD_TARGET (if set) once per process; the field kernels
// call it before they dispatch. Throws as limit_targets, naming the variable.
void apply_environment();

// Marks the upper halves of the AVX registers unused (vzeroupper) on CPUs
// that have them; no-op elsewhere. While they are marked in use, code built
// for baseline x86-64 (SSE: every scalar kernel) waits on them on Intel
// CPUs, and libraries in the application leave them so: the scalar 12R
// kernel ran at half speed in `linkscape` until the field loop called this
// before each chunk of rows.
void clear_upper_registers();

}  // namespace linkscape::simd
