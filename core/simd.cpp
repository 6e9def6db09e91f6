// Highway compiles the part between HWY_BEFORE_NAMESPACE and
// HWY_AFTER_NAMESPACE once per target (foreach_target.h re-includes this
// file); the rest, under HWY_ONCE, once.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace linkscape::simd::HWY_NAMESPACE {
std::int64_t TargetBit() { return HWY_TARGET; }
}  // namespace linkscape::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "core/simd.h"

namespace linkscape::simd {
namespace {

HWY_EXPORT(TargetBit);

// Compiled and supported targets (Highway bits, best = lowest first), taken
// before any limit is set.
const std::vector<std::int64_t>& target_bits() {
  static const std::vector<std::int64_t> bits = hwy::SupportedAndGeneratedTargets();
  return bits;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  return s;
}

}  // namespace

std::vector<std::string> available_targets() {
  std::vector<std::string> names;
  for (std::int64_t bit : target_bits()) names.emplace_back(hwy::TargetName(bit));
  return names;
}

std::string current_target() { return hwy::TargetName(HWY_DYNAMIC_DISPATCH(TargetBit)()); }

std::string highway_version() {
  return std::to_string(HWY_MAJOR) + "." + std::to_string(HWY_MINOR) + "." + std::to_string(HWY_PATCH);
}

void limit_targets(const std::string& name) {
  const std::vector<std::int64_t>& bits = target_bits();
  if (name.empty()) {
    hwy::DisableTargets(0);
    return;
  }
  if (upper(name) == "BASELINE") {
    limit_targets(available_targets().back());
    return;
  }
  for (std::int64_t bit : bits)
    if (upper(name) == hwy::TargetName(bit)) {
      hwy::DisableTargets(bit - 1);  // every better target has a lower bit
      return;
    }
  std::string list;
  for (const std::string& n : available_targets()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("SIMD target '" + name + "' is not available on this CPU; available: " + list);
}

void apply_environment() {
  static std::once_flag once;
  std::call_once(once, [] {
    const char* value = std::getenv("LINKSCAPE_SIMD_TARGET");
    if (!value || !*value) return;
    try {
      limit_targets(value);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("LINKSCAPE_SIMD_TARGET: ") + e.what());
    }
  });
}

void clear_upper_registers() {
#if HWY_ARCH_X86_64 && (defined(__GNUC__) || defined(__clang__))
  static const bool has_avx = __builtin_cpu_supports("avx");
  if (has_avx) asm volatile("vzeroupper");
#endif
}

}  // namespace linkscape::simd

#endif  // HWY_ONCE
