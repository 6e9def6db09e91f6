// FUZZ_CHECK for the fuzz targets: a broken invariant prints what was
// expected and the values involved, then aborts, so libFuzzer keeps the input
// as a crash and the corpus replay test fails.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <string>

namespace linkscape::fuzz {

[[noreturn]] inline void fail(const char* file, int line, const char* condition, const std::string& detail) {
  std::fprintf(stderr, "%s:%d: invariant broken: %s\n  %s\n", file, line, condition, detail.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace linkscape::fuzz

// FUZZ_CHECK(condition, stream expression): FUZZ_CHECK(a <= b, "a=" << a << " b=" << b).
#define FUZZ_CHECK(condition, detail)                                               \
  do {                                                                              \
    if (!(condition)) {                                                             \
      std::ostringstream fuzz_detail_;                                              \
      fuzz_detail_ << std::setprecision(17) << detail;                              \
      ::linkscape::fuzz::fail(__FILE__, __LINE__, #condition, fuzz_detail_.str()); \
    }                                                                               \
  } while (0)
