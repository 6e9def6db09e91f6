// Hand-made fields for render tests.
#pragma once

#include "core/field.h"

namespace linkscape::render::testing {

// A field on `grid` whose per-sample arrays (method_used included) are sized
// to it, their values left for the test to fill.
inline Field sized_field(const Grid& grid, const std::string& length_unit = "cm") {
  Field f;
  f.grid = grid;
  f.length_unit = length_unit;
  const std::size_t n = grid.size();
  for (auto* a : {&f.cond, &f.reach_margin, &f.residual}) a->resize(n);
  for (auto* a : {&f.reachable, &f.status, &f.method_used}) a->resize(n);
  f.iterations.resize(n);
  return f;
}

}  // namespace linkscape::render::testing
