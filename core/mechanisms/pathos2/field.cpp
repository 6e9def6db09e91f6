#include "core/mechanisms/pathos2/field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <atomic>

#include "core/field_sampling.h"
#include "core/mechanisms/pathos2/stops.h"
#include "core/simd.h"

namespace linkscape::pathos2 {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kDeg = std::numbers::pi / 180.0;

// Margin of one leg to its reach: the shell of Eq. 14's c2z root and the
// cylinder of its c1x root, both in the leg frame (cm).
double leg_reach_margin(const Model& m, const Eigen::Vector3d& a) {
  const double dz = a.z() - m.l1;
  const double rxy = std::hypot(a.x(), a.y());
  const double rho = std::hypot(rxy, dz);
  const double shell = std::min(m.l2 + m.l3 - rho, rho - std::abs(m.l2 - m.l3));
  // c1y^2 = l3^2 - (c2z - l2)^2; the root c1x = sqrt(rxy^2 - c1y^2) needs rxy >= |c1y|.
  const double e = (m.l2 * m.l2 - m.l3 * m.l3 + rho * rho) / (2.0 * m.l2) - m.l2;
  const double c1y = std::sqrt(std::max(0.0, m.l3 * m.l3 - e * e));
  return std::min(shell, rxy - c1y);
}

// The same from the leg's IK (its c1y is the one above to rounding: there
// from |a - l1 z|^2, here from hypot's rho squared) with sqrt(x^2 + y^2) for
// hypot, which cost a call and a quarter of the field's time. They differ by
// an ulp or two of rxy and rho, and where e is near +-l3 by up to sqrt(u) l3
// in c1y (the reference is as far from the exact value there). Out of the
// range where the squares neither overflow nor underflow, hypot.
double leg_reach_margin_from_ik(const Model& m, const LegSolution& leg) {
  const Eigen::Vector3d& a = leg.p_B_globular;
  const double dz = a.z() - m.l1;
  const double rxy2 = a.x() * a.x() + a.y() * a.y();
  const double rho2 = rxy2 + dz * dz;
  if (!(rho2 <= 1e300 && rxy2 >= 1e-290)) return leg_reach_margin(m, a);
  const double rxy = std::sqrt(rxy2), rho = std::sqrt(rho2);
  const double shell = std::min(m.l2 + m.l3 - rho, rho - std::abs(m.l2 - m.l3));
  return std::min(shell, rxy - std::abs(leg.c1y));
}

// reach_margin with the leg margin `leg_margin(model, leg)`.
template <class LegMargin>
double reach_margin_with(const Geometry& g, const PoseIkResult& ik, LegMargin leg_margin) {
  const Model& m = g.model;
  constexpr double pi = std::numbers::pi;
  double margin = std::numeric_limits<double>::infinity();
  for (const LegSolution& leg : ik.legs) {
    margin = std::min(margin, leg_margin(m, leg));
    if (leg.status == Status::Unreachable) continue;  // the angles below are not set
    // Joint limits, where set: angle margin times the radius it swings.
    if (m.t2_limit < pi) margin = std::min(margin, (m.t2_limit - std::abs(leg.t2)) * (m.l2 + m.l3));
    if (m.t3_limit < pi) margin = std::min(margin, (m.t3_limit - std::abs(leg.t3)) * m.l3);
    if (m.cone_limit < pi) margin = std::min(margin, (m.cone_limit - leg.t5) * m.l3);
  }
  return margin;
}

}  // namespace

double reach_margin(const Geometry& g, const PoseIkResult& ik) {
  return reach_margin_with(g, ik, [](const Model& m, const LegSolution& leg) { return leg_reach_margin(m, leg.p_B_globular); });
}

namespace {

// Eq. 3 as leg_forward computes it, Rz(t1)[Tz(l1) + Ry(t2){Tz(l2) + Rx(t3)
// Tz(l3)}], from the cosines and sines the IK found instead of the angles.
Eigen::Vector3d leg_end(const Model& m, const LegSolution& leg) {
  const double y = -m.l3 * leg.sin_t3, z = m.l2 + m.l3 * leg.cos_t3;  // Rx(t3) Tz(l3) + Tz(l2)
  const double x1 = leg.sin_t2 * z, z1 = m.l1 + leg.cos_t2 * z;        // Tz(l1) + Ry(t2) (0, y, z)
  return {leg.cos_t1 * x1 - leg.sin_t1 * y, leg.sin_t1 * x1 + leg.cos_t1 * y, z1};
}

// The sample at `pose`: without `offsets` the reference (the Full IK); with
// the pose's globular offsets the Field IK, where the closure residual comes
// from the legs' cosines and sines (leg_end) instead of their angles and the
// reach margin from leg_reach_margin_from_ik, both within rounding of the
// reference (the residual is itself rounding noise, about 1e-15 cm), every
// other array bit for bit.
FieldSample sample_pose(const Geometry& g, const Pose& pose, const GlobularOffsets* offsets) {
  const Model& m = g.model;
  const IkDetail detail = offsets ? IkDetail::Field : IkDetail::Full;
  const PoseIkResult ik = offsets ? inverse_field_sample(g, pose, *offsets) : inverse(g, pose);
  FieldSample s;
  s.reach_margin = float(detail == IkDetail::Field ? reach_margin_with(g, ik, leg_reach_margin_from_ik)
                                                    : reach_margin(g, ik));
  s.status = std::uint8_t(ik.status);
  s.reachable = ik.status == Status::Ok;
  s.cond = s.cond_orientation = kInf;
  s.residual = kInf;
  if (ik.status == Status::Ok || ik.status == Status::OutOfLimits) {
    double closure = 0.0;
    for (const LegSolution& leg : ik.legs)
      closure = std::max(closure, ((detail == IkDetail::Field ? leg_end(m, leg)
                                                               : leg_forward(m.l1, m.l2, m.l3, leg.t1, leg.t2, leg.t3)) -
                                   leg.p_B_globular)
                                      .norm());
    s.residual = float(closure);
  }
  if (s.reachable) {
    const JacobianResult J = jacobian(g, pose, ik);
    if (J.status == Status::Ok) {
      s.cond = float(J.cond_p);
      s.cond_orientation = float(J.cond_o);
    } else {
      // The pose is solved but J is singular to working precision
      // (kMaxJacobianCondition): singular, cond +inf, as the 12R field does.
      s.status = std::uint8_t(J.status);
      s.reachable = 0;
    }
  }
  return s;
}

}  // namespace

FieldSample sample_oriented(const Geometry& g, const Pose& oriented, const GlobularOffsets& offsets,
                            const Eigen::Vector3d& p) {
  Pose pose = oriented;
  pose.p_world_E = p;
  return sample_pose(g, pose, &offsets);
}

FieldSetup field_setup(const Geometry& g, const Pose& oriented, const GlobularOffsets& offsets) {
  const Model& m = g.model;
  constexpr double pi = std::numbers::pi;
  FieldSetup s;
  for (int i = 0; i < kLegCount; ++i) {
    FieldSetup::Leg& leg = s.legs[i];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) leg.R[3 * r + c] = g.R_world_B[i](r, c);
    // As inverse_with forms it (a 3x3 product, then its z column).
    const Eigen::Matrix3d R_world_A = oriented.R_world_E * g.R_E_A[i];
    const Eigen::Vector3d z_A = R_world_A.col(2), z_A_in_B = g.R_world_B[i].transpose() * z_A;
    for (int k = 0; k < 3; ++k) {
      leg.p_B[k] = g.p_world_B[i](k);
      leg.offset[k] = offsets[i](k);
      leg.z_A[k] = z_A(k);
      leg.z_A_in_B[k] = z_A_in_B(k);
    }
    leg.branch_sign = m.branch[i] >= 0 ? 1.0 : -1.0;
  }
  s.cos_cone = std::cos(m.cone_limit);
  s.cos_t2 = std::cos(m.t2_limit);
  s.cos_t3 = std::cos(m.t3_limit);
  s.check_cone = m.cone_limit < pi;
  s.check_t2 = m.t2_limit < pi;
  s.check_t3 = m.t3_limit < pi;
  s.length_scale = std::ldexp(1.0, std::ilogb(m.l2 + m.l3));
  return s;
}

namespace {

// The stops' arrays of a field (stops.h): null where the model states none.
struct StopArrays {
  float* joint_margin = nullptr;
  float* clearance = nullptr;
  bool any() const { return joint_margin || clearance; }
};

StopArrays add_stop_arrays(Field& f, const Model& m) {
  StopArrays a;
  if (has_joint_limits(m))
    a.joint_margin = f.add_extra("joint_margin", "joint margin", "deg",
                               "How far the nearest limited joint is from its limit (< 0 beyond it; none where a leg "
                               "does not close)");
  if (has_capsules(m))
    a.clearance = f.add_extra("clearance", "clearance", "cm",
                            "The smallest gap between two legs' links or a link and the grip (< 0 where they overlap; "
                            "none where a leg does not close)");
  return a;
}

// A scalar pass over a row the kernel filled: each assembled sample's stops
// (NaN where a leg does not close), and an ok sample whose links overlap
// becomes out-of-limits with its reach margin at most the clearance (its
// joint limits are the kernel's already).
void stops_of_row(const Geometry& g, const Pose& oriented, const GlobularOffsets& offsets, const Grid& grid,
                  const detail::GridRow& row, const detail::FieldRowOut& out, const StopArrays& arrays) {
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  std::atomic_thread_fence(std::memory_order_seq_cst);  // after the kernel's streaming stores
  Pose pose = oriented;
  for (int t = 0; t < row.count; ++t) {
    const std::size_t i = row.index + std::size_t(t);
    float margin = nan, gap = nan;
    if (out.status[t] != std::uint8_t(Status::Unreachable)) {
      pose.p_world_E = row.point(grid, t);
      const PoseIkResult ik = inverse_field_sample(g, pose, offsets);
      const bool closes = std::none_of(ik.legs.begin(), ik.legs.end(),
                                       [](const LegSolution& l) { return l.status == Status::Unreachable; });
      if (closes) {
        const Stops st = stops(g, pose, ik);
        margin = float(st.joint_margin_deg), gap = float(st.clearance);
        if (arrays.clearance) out.reach_margin[t] = std::min(out.reach_margin[t], gap);
        if (st.clearance < 0 && out.status[t] == std::uint8_t(Status::Ok)) {
          out.status[t] = std::uint8_t(Status::OutOfLimits);
          out.reachable[t] = 0;
          out.cond[t] = kInf;
          if (out.cond_orientation) out.cond_orientation[t] = kInf;
        }
      }
    }
    if (arrays.joint_margin) arrays.joint_margin[i] = margin;
    if (arrays.clearance) arrays.clearance[i] = gap;
  }
}

}  // namespace

FieldSample sample_position(const Geometry& g, const Eigen::Vector3d& p, const FieldRequest& req) {
  const Pose pose = Pose::from_xyz_rpy(p.x(), p.y(), p.z(), req.rpy.x(), req.rpy.y(), req.rpy.z(), req.h0);
  return sample_pose(g, pose, nullptr);
}

std::optional<Field> compute_field(const Model& model, const FieldRequest& req, const FieldProgress& progress) {
  if (!req.rpy.allFinite() || !std::isfinite(req.h0) || !(req.h0 > 0))
    throw std::invalid_argument("pathos2 field: orientation must be finite and the grip h0 > 0");
  const Geometry g = make_geometry(model);  // validates the model
  const std::size_t stop_bytes = sizeof(float) * (std::size_t(has_joint_limits(model)) + std::size_t(has_capsules(model)));
  detail::check_grid(req.grid, Field::bytes_per_sample() + sizeof(float) + stop_bytes, req.memory_limit_bytes);
  Field f;
  f.grid = req.grid;
  f.mechanism = std::string(kMechanismName);
  f.length_unit = "cm";
  f.parameters = model.to_parameters();
  f.parameters["rx"] = req.rpy.x() / kDeg;
  f.parameters["ry"] = req.rpy.y() / kDeg;
  f.parameters["rz"] = req.rpy.z() / kDeg;
  f.parameters["h0"] = req.h0;  // the grip sampled, which may differ from the model default
  f.method = "closed-form";
  f.measure_titles = {"cond(Jp)", "cond(Jo)"};
  f.branch = 0;
  const FieldKernel kernel = req.kernel ? *req.kernel : field_kernel_from_environment();
  // from_xyz_rpy sets the position alone from x, y, z: the rotation is the grid's.
  const Pose oriented = Pose::from_xyz_rpy(0.0, 0.0, 0.0, req.rpy.x(), req.rpy.y(), req.rpy.z(), req.h0);
  inverse(g, oriented, IkDetail::ActiveOnly);  // checks the rotation and grip once: IkDetail::Field does not
  const GlobularOffsets offsets = globular_offsets(g, oriented);
  const StopArrays stop_arrays = add_stop_arrays(f, g.model);
  const auto with_stops = [&](auto&& kernel_row) {
    return [&, kernel_row](const detail::GridRow& row, const detail::FieldRowOut& out) {
      kernel_row(row, out);
      if (stop_arrays.any()) stops_of_row(g, oriented, offsets, req.grid, row, out, stop_arrays);
    };
  };
  bool complete = false;
  if (kernel == FieldKernel::Scalar) {
    complete = detail::fill_field_rows(f, true, req.threads, progress,
                                       with_stops([&](const detail::GridRow& row, const detail::FieldRowOut& out) {
                                         for (int t = 0; t < row.count; ++t)
                                           out.store(t, sample_position(g, row.point(req.grid, t), req));
                                       }));
  } else {
    simd::apply_environment();
    const FieldSetup setup = field_setup(g, oriented, offsets);
    complete = detail::fill_field_rows(f, true, req.threads, progress,
                                       with_stops([&](const detail::GridRow& row, const detail::FieldRowOut& out) {
                                         sample_row_vector(g, setup, oriented, offsets, req.grid, row, out);
                                       }),
                                       detail::kVectorChunkSamples);
  }
  if (!complete) return std::nullopt;
  return f;
}

}  // namespace linkscape::pathos2
