#include "core/mechanisms/delta/field.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <cmath>
#include <numbers>

#include "core/field_sampling.h"
#include "core/grid_mirror.h"
#include "core/mechanisms/delta/stops.h"
#include "core/simd.h"

namespace linkscape::delta {
FieldSample sample_point(const Model& m, const Eigen::Vector3d& p, const FieldRequest& req) {
  const int branch = req.ik.branch;
  FieldSample s;
  const IkResult r = inverse(m, p, req.method, req.ik);
  s.reach_margin = float(reach_margin(m, p, branch).value);
  s.status = std::uint8_t(r.status);
  s.iterations = std::uint16_t(std::min(r.iterations, 65535));
  s.reachable = r.status == Status::Ok && r.branch == branch;
  s.residual = r.status == Status::Unreachable ? std::numeric_limits<float>::infinity() : float(r.residual);
  s.cond = std::numeric_limits<float>::infinity();
  if (s.reachable) {
    s.cond = float(jacobian(m, r.q_actuated, p).cond);
    s.method_used = req.method == IkMethod::Closed ? 0 : 1;
  }
  return s;
}

float cones_of_sample(const Model& m, const Eigen::Vector3d& p, const FieldRequest& req, FieldSample& s) {
  if (s.status == std::uint8_t(Status::Unreachable)) return std::numeric_limits<float>::quiet_NaN();
  // Each leg's closed form on the field's branch, as inverse() solves it.
  Eigen::Vector3d q;
  for (int leg = 0; leg < kLegCount; ++leg) {
    const LegSolution l = leg_inverse(m, leg, p, (req.ik.branch >> leg) & 1);
    if (l.status == Status::Unreachable) return std::numeric_limits<float>::quiet_NaN();
    q(leg) = l.q;
  }
  const JointStops st = joint_stops(m, q, p);
  s.reach_margin = std::min(s.reach_margin, float(m.size() * st.margin_deg * std::numbers::pi / 180));
  if (!st.hold() && s.status == std::uint8_t(Status::Ok)) {
    s.status = std::uint8_t(Status::OutOfLimits);
    s.reachable = 0;
    s.cond = std::numeric_limits<float>::infinity();
  }
  return float(st.margin_deg);
}

bool mirror_holds(const Model& m, const FieldRequest& req) {
  const auto& q = m.q_limits;
  const int branch = req.ik.branch;
  if (q[1].lo != q[2].lo || q[1].hi != q[2].hi || ((branch >> 1) & 1) != ((branch >> 2) & 1)) return false;
  return detail::mirrors_in_y(req.grid);
}

std::optional<Field> compute_field(const Model& m, const FieldRequest& req, const FieldProgress& progress) {
  m.validate();
  if (req.ik.branch < 0 || req.ik.branch >= kBranchCount) throw std::invalid_argument("delta: branch must be 0..7");
  detail::check_grid(req.grid, Field::bytes_per_sample() + (m.has_cones() ? sizeof(float) : 0), req.memory_limit_bytes);
  const FieldKernel kernel = req.kernel ? *req.kernel : field_kernel_from_environment();
  Field f;
  f.grid = req.grid;
  f.mechanism = std::string(kMechanismName);
  f.length_unit = m.length_unit;
  f.parameters = m.to_parameters();
  f.method = std::string(to_string(req.method));
  for (IkMethod k : {IkMethod::Closed, IkMethod::Newton}) f.method_names.emplace_back(to_string(k));  // by IkMethod value
  f.branch = req.ik.branch;
  const Grid& g = req.grid;
  const bool fast = kernel != FieldKernel::Scalar && req.method == IkMethod::Closed;
  const FieldLegs legs = field_legs(m);
  if (fast) simd::apply_environment();
  const bool mirrored = fast && kernel == FieldKernel::VectorMirrored && mirror_holds(m, req);
  float* joint_margin = m.has_cones() ? f.add_extra("joint_margin", "joint margin", "deg",
                                                   "How far the nearest ball joint is from its cone (< 0 beyond it; "
                                                   "none where a leg does not close)")
                                      : nullptr;
  const bool complete = detail::fill_field_rows(
      f, false, req.threads, progress,
      [&](const detail::GridRow& row, const detail::FieldRowOut& out) {
        if (mirrored) {
          const detail::RowImage image = detail::image_in_y(g, row);
          if (!image.sampled) return;
          if (image.image) {
            RowMirror mirror{*image.image, out.shifted(image.by)};
            sample_row_vector(m, legs, req, g, row, out, &mirror, joint_margin);
            return;
          }
        }
        if (fast) {
          sample_row_vector(m, legs, req, g, row, out, nullptr, joint_margin);
          return;
        }
        for (int t = 0; t < row.count; ++t) {
          const Eigen::Vector3d p = row.point(g, t);
          FieldSample s = sample_point(m, p, req);
          if (joint_margin) joint_margin[row.index + std::size_t(t)] = cones_of_sample(m, p, req, s);
          out.store(t, s);
        }
      },
      fast ? detail::kVectorChunkSamples : detail::kChunkSamples);
  if (!complete) return std::nullopt;
  return f;
}

}  // namespace linkscape::delta
