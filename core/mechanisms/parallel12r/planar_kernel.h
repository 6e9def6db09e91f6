// The 12R planar field kernel, internal to core: the scalar reference
// (field.cpp) and the same computation on rows of samples with SIMD vectors
// (field_simd.cpp, Highway with run-time dispatch). The two agree as
// tests/core/mechanisms/parallel12r/test_field_simd.cpp states: the same
// statuses and infinities, finite values within the tolerance given there.
#pragma once

#include <Eigen/Core>

#include "core/field_sampling.h"
#include "core/mechanisms/parallel12r/parallel12r.h"
#include "core/status.h"

namespace linkscape::parallel12r::planar {

// The model with lengths divided by a power of two near its reach (exact):
// angles and c(J) do not depend on scale, and in these units no product in
// the planar closed form (up to length^4) can overflow or underflow.
struct UnitModel {
  Model unit;
  double to_unit = 1.0, from_unit = 1.0;  // 2^-e and 2^e: lengths of the model = unit lengths * 2^e
};
UnitModel unit_model(const Model& m);

// One sample as the kernel computes it, in double and in the model's units
// (the Field stores float). The status decides the rest: reachable where Ok,
// method_used Planar where Ok or OutOfLimits (else none), no iterations;
// cond is +inf unless Ok, residual +inf where there is no solution.
struct Sample {
  double cond = 0, reach_margin = 0, residual = 0;
  Status status = Status::Ok;
};

// Both ends of a limits check need the angles only when a range is not full.
bool full_ranges(const Model& m);

// The scalar reference at one point p (model units).
Sample sample(const UnitModel& u, const Eigen::Vector3d& p, int branch, bool check_limits);

// Sample s as the Field stores it.
inline FieldSample to_field_sample(const Sample& s) {
  FieldSample f;
  f.cond = float(s.cond);
  f.reach_margin = float(s.reach_margin);
  f.residual = float(s.residual);
  f.status = std::uint8_t(s.status);
  f.reachable = s.status == Status::Ok;
  const bool solved = s.status == Status::Ok || s.status == Status::OutOfLimits;
  f.method_used = solved ? std::uint8_t(IkMethod::Planar) : Field::kNoMethod;
  return f;
}

// The same kernel on samples [first, first + count) of a grid row, with SIMD
// vectors of the best instruction set this CPU has (simd::current_target()),
// written into out at t = first .. first + count - 1; with `mirror` also at
// row.count - 1 - t (the caller has checked that the mirror is exact).
void sample_row_vector(const UnitModel& u, int branch, bool check_limits, const Grid& g, const detail::GridRow& row,
                       int first, int count, bool mirror, const detail::FieldRowOut& out);

}  // namespace linkscape::parallel12r::planar
