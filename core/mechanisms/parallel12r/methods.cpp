#include "core/mechanisms/parallel12r/methods.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/mechanisms/parallel12r/field.h"

namespace linkscape::methods {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using parallel12r::IkMethod;
using parallel12r::Model;

// Elementary functions per precision.
inline long double m_sin(long double v) { return sinl(v); }
inline long double m_cos(long double v) { return cosl(v); }
inline long double m_sqrt(long double v) { return sqrtl(v); }
template <class T>
T unit_roundoff();
template <>
long double unit_roundoff<long double>() { return std::numeric_limits<long double>::epsilon() / 2; }

template <class T>
using V3 = std::array<T, 3>;
template <class T>
using M3 = std::array<std::array<T, 3>, 3>;  // [row][col]

// Eqs. 11-13 and their analytic derivatives, as in parallel12r.cpp, in T.
template <class T>
struct Kinematics {
  V3<T> p;
  M3<T> J;
};

template <class T>
Kinematics<T> kinematics(T L1, T L2, const V3<T>& q) {
  const T sa = m_sin(q[0]), ca = m_cos(q[0]);
  Kinematics<T> k{};
  const T L[2] = {L1, L2};
  for (int link = 0; link < 2; ++link) {
    const T t = q[1 + link];
    const T st = m_sin(t), ct = m_cos(t);
    // d^2 = 1 - sin^2 a sin^2 t written without cancellation: near the
    // actuator plane (sin a -> 1, sin t -> 1) the printed form loses
    // digits in proportion to 1/d^2 (see docs/methods.md).
    const T d2 = ca * ca + sa * sa * ct * ct;
    const T d = m_sqrt(d2), d3 = d2 * d;
    const T u[3] = {-sa * ct / d, ca * ct / d, ca * st / d};
    const T du_da[3] = {-ca * ct / d3, -sa * ct * ct * ct / d3, -sa * st * ct * ct / d3};
    const T du_dt[3] = {ca * sa * ca * st / d3, -ca * ca * ca * st / d3, ca * ct / d3};
    for (int r = 0; r < 3; ++r) {
      k.p[r] += L[link] * u[r];
      k.J[r][0] += L[link] * du_da[r];
      k.J[r][1 + link] = L[link] * du_dt[r];
    }
  }
  return k;
}

// Solves J x = b by Cramer's rule (3x3; fine in extended precision).
template <class T>
std::optional<V3<T>> solve3(const M3<T>& J, const V3<T>& b) {
  auto det = [](const M3<T>& A) {
    return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
           A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  };
  const T D = det(J);
  if (D == T(0)) return std::nullopt;
  V3<T> x;
  for (int c = 0; c < 3; ++c) {
    M3<T> A = J;
    for (int r = 0; r < 3; ++r) A[r][c] = b[r];
    x[c] = det(A) / D;
  }
  return x;
}

template <class T>
T norm(const V3<T>& v) {
  return m_sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

constexpr double kPi = std::numbers::pi;

long double wrap_ld(long double a) {
  const long double two_pi = 2.0L * std::numbers::pi_v<long double>;
  a = std::remainder(a, two_pi);
  return a <= -std::numbers::pi_v<long double> ? a + two_pi : a;
}

template <class T>
ReferenceSolution newton_reference(const Model& m, const Vector3d& target, const Vector3d& seed) {
  const T L1 = T(m.L1), L2 = T(m.L2);
  const V3<T> p{T(target.x()), T(target.y()), T(target.z())};
  V3<T> q{T(seed.x()), T(seed.y()), T(seed.z())};
  auto residual_of = [&](const V3<T>& qq, V3<T>* r) {
    const Kinematics<T> k = kinematics(L1, L2, qq);
    V3<T> e{p[0] - k.p[0], p[1] - k.p[1], p[2] - k.p[2]};
    if (r) *r = e;
    return norm(e);
  };
  V3<T> e;
  T res = residual_of(q, &e);
  // The residual cannot fall below the rounding of q itself times |J|
  // (|J| reaches 1e7 near the actuator plane) plus that of the target.
  auto floor_of = [&](const Kinematics<T>& k) {
    T j2 = 0;
    for (const auto& row : k.J)
      for (T v : row) j2 += v * v;
    return unit_roundoff<T>() * (T(m.reach()) + T(kPi) * m_sqrt(j2));
  };
  const T stop = T(8) * floor_of(kinematics(L1, L2, q));
  int it = 0;
  for (; it < 200 && res > stop; ++it) {
    const Kinematics<T> k = kinematics(L1, L2, q);
    const auto step = solve3(k.J, e);
    if (!step) break;
    T t = T(1);
    bool improved = false;
    for (int h = 0; h < 60; ++h, t = t / T(2)) {
      const V3<T> trial{q[0] + t * (*step)[0], q[1] + t * (*step)[1], q[2] + t * (*step)[2]};
      V3<T> e_trial;
      const T r = residual_of(trial, &e_trial);
      if (r < res) {
        q = trial;
        e = e_trial;
        res = r;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  ReferenceSolution s;
  s.iterations = it;
  s.residual = static_cast<long double>(res);
  s.converged = res <= T(1000) * floor_of(kinematics(L1, L2, q));
  // alpha in (-pi/2, pi/2]: u(a + pi, t + pi) = u(a, t).
  for (int k = 0; k < 3; ++k) s.q[k] = wrap_ld(static_cast<long double>(q[k]));
  if (cosl(s.q[0]) < 0)
    for (int k = 0; k < 3; ++k) s.q[k] = wrap_ld(s.q[k] + std::numbers::pi_v<long double>);
  s.q_actuated = Vector3d(double(s.q[0]), double(s.q[1]), double(s.q[2]));
  s.branch = sinl(s.q[1] - s.q[2]) >= 0 ? 0 : 1;
  return s;
}

template <class T>
Vector3d forward_t(const Model& m, const Eigen::Matrix<T, 3, 1>& q) {
  // Generic forward for complex-step differentiation.
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T sa = sin(q(0)), ca = cos(q(0));
  Eigen::Matrix<T, 3, 1> p = Eigen::Matrix<T, 3, 1>::Zero();
  const double L[2] = {m.L1, m.L2};
  for (int link = 0; link < 2; ++link) {
    const T st = sin(q(1 + link)), ct = cos(q(1 + link));
    const T d = sqrt(ca * ca + sa * sa * ct * ct);  // as in kinematics<T>
    p += L[link] * Eigen::Matrix<T, 3, 1>(-sa * ct / d, ca * ct / d, ca * st / d);
  }
  if constexpr (std::is_same_v<T, std::complex<double>>)
    return p.imag();
  else
    return p;
}


volatile double g_sink = 0;  // keeps timed results alive

std::string format_step(double h) {
  std::ostringstream s;
  s.precision(2);
  s << "h=" << h;
  return s.str();
}

// A row of this harness's table.
MethodRow new_row(const std::string& family, const std::string& method, const std::string& unit) {
  MethodRow row;
  row.mechanism = std::string(parallel12r::kMechanismName);
  row.family = family;
  row.method = method;
  row.error_unit = unit;
  return row;
}

// The planar closed form (docs/mechanisms/parallel-12r.md) without any
// check through Eqs. 11-13, as a seed: clamped into the shell, so it gives
// a configuration for any target off the z axis.
std::optional<Vector3d> planar_seed(const Model& m, const Vector3d& p, int branch) {
  const double rho = std::hypot(p.x(), p.y());
  if (!(rho > 0)) return std::nullopt;
  const double sign_y = p.y() >= 0 ? 1.0 : -1.0;
  const double ca = std::abs(p.y()) / rho, r = sign_y * rho;
  const double R = std::clamp(p.norm(), std::max(m.inner_reach(), 1e-300), m.reach());
  const double L1 = m.L1, L2 = m.L2;
  const double a = (R * R + L1 * L1 - L2 * L2) / (2.0 * R);
  const double h = std::sqrt(std::max(0.0, (L1 + L2 - R) * (L2 - L1 + R) * (R + L1 - L2) * (R + L1 + L2)) / (4.0 * R * R));
  const double ur = r / p.norm(), uz = p.z() / p.norm(), s = branch == 0 ? 1.0 : -1.0;
  const double l1r = a * ur - s * h * uz, l1z = a * uz + s * h * ur;
  const double l2r = R * ur - l1r, l2z = R * uz - l1z;
  return Vector3d(std::atan2(-p.x() * sign_y, std::abs(p.y())), std::atan2(l1z, ca * l1r), std::atan2(l2z, ca * l2r));
}

}  // namespace

// ---- References ---------------------------------------------------------------

ReferenceSolution reference_inverse(const Model& m, const Vector3d& target, const Vector3d& seed) {
  m.validate();
  if (!target.allFinite() || !seed.allFinite())
    throw std::invalid_argument("reference_inverse: target and seed must be finite");
  return newton_reference<long double>(m, target, seed);
}

IkReference reference_ik(const Model& m, const Vector3d& target, const std::optional<Vector3d>& hint) {
  IkReference ref;
  std::vector<Vector3d> seeds;
  if (hint) seeds.push_back(*hint);
  for (int branch = 0; branch < 2; ++branch)
    if (const auto q = planar_seed(m, target, branch)) seeds.push_back(*q);
  for (const Vector3d& seed : seeds) {
    const ReferenceSolution s = reference_inverse(m, target, seed);
    if (!s.converged) continue;
    if (!ref.branch[s.branch]) ref.branch[s.branch] = s;
  }
  return ref;
}

double joint_error(const Vector3d& q, const ReferenceSolution& r) {
  long double best = std::numeric_limits<long double>::infinity();
  for (long double shift : {0.0L, std::numbers::pi_v<long double>}) {
    long double e = 0;
    for (int k = 0; k < 3; ++k) e = std::max(e, fabsl(wrap_ld((long double)q(k) + shift - r.q[k])));
    best = std::min(best, e);
  }
  return double(best);
}

Matrix3d reference_jacobian(const Model& m, const Vector3d& q) {
  const Kinematics<long double> k = kinematics<long double>(m.L1, m.L2, {q.x(), q.y(), q.z()});
  Matrix3d J;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) J(r, c) = double(k.J[r][c]);
  return J;
}

double backward_error_scale(const Model& m, const Vector3d& q) {
  // forward() writes d^2 = cos^2 a + sin^2 a cos^2 t (no cancellation), so
  // Eqs. 11-13 add only a few u (L1 + L2) of their own.
  return m.reach() + kPi * reference_jacobian(m, q).norm();
}

Matrix3d jacobian_forward_difference(const Model& m, const Vector3d& q, double step) {
  const Vector3d p0 = parallel12r::forward(m, q);
  Matrix3d J;
  for (int k = 0; k < 3; ++k) {
    Vector3d dq = Vector3d::Zero();
    dq(k) = step;
    J.col(k) = (parallel12r::forward(m, q + dq) - p0) / step;
  }
  return J;
}

Matrix3d jacobian_complex_step(const Model& m, const Vector3d& q, double step) {
  using C = std::complex<double>;
  Matrix3d J;
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix<C, 3, 1> qc = q.cast<C>();
    qc(k) += C(0.0, step);
    J.col(k) = forward_t<C>(m, qc) / step;
  }
  return J;
}

// ---- One IK evaluation ------------------------------------------------------------

IkMeasurement measure_ik(const Model& m, const Vector3d& target, const IkReference& ref, IkMethod method,
                         const parallel12r::IkOptions& options) {
  const parallel12r::IkResult r = parallel12r::inverse(m, target, method, options);
  IkMeasurement out;
  out.status = r.status;
  out.error = std::numeric_limits<double>::quiet_NaN();
  double worst = -1;
  for (const auto& s : r.solutions) {
    out.iterations = std::max(out.iterations, s.iterations);
    if (s.status != Status::Ok) continue;
    ++out.solutions_ok;
    if (s.method == IkMethod::Newton && method == IkMethod::Fallback) ++out.from_newton;
    out.residual = std::max(out.residual, s.residual);
    // Compared with the nearest exact solution: near the spheres the two
    // branches merge and a solver's branch label may be either.
    double e = std::numeric_limits<double>::infinity();
    for (const auto& rb : ref.branch)
      if (rb) e = std::min(e, joint_error(s.q_actuated, *rb));
    worst = std::max(worst, e);
  }
  if (out.solutions_ok > 0) out.error = worst;
  return out;
}

// ---- Harness ---------------------------------------------------------------------

parallel12r::IkOptions ik_options(const SolverLimits& limits) {
  parallel12r::IkOptions ik;
  ik.tolerance = limits.tolerance;
  ik.max_iterations = limits.max_iterations;
  return ik;
}

std::vector<Vector3d> workspace_targets(const Model& m, std::size_t count, unsigned seed) {
  m.validate();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-m.reach(), m.reach());
  std::vector<Vector3d> out;
  out.reserve(count);
  while (out.size() < count) {
    const Vector3d p(u(rng), u(rng), u(rng));
    const double r = p.norm();
    if (r < m.reach() && r > m.inner_reach()) out.push_back(p);
  }
  return out;
}

namespace {

struct Sample {
  Vector3d target;
  IkReference ref;
  Vector3d q;  // branch-0 reference configuration (or branch 1 if only that)
  Matrix3d J;  // analytic Jacobian at q (double)
};

void ik_rows(const Model& m, const std::vector<Sample>& samples, const HarnessOptions& o, std::vector<MethodRow>& rows) {
  const parallel12r::IkOptions ik = ik_options(o.ik);
  for (IkMethod method : {IkMethod::Paper, IkMethod::Planar, IkMethod::Newton, IkMethod::DampedLeastSquares,
                          IkMethod::Fallback}) {
    MethodRow row = new_row("ik", std::string(parallel12r::to_string(method)), "rad");
    std::vector<double> errors;
    for (const Sample& s : samples) {
      const IkMeasurement r = measure_ik(m, s.target, s.ref, method, ik);
      if (r.status != Status::Ok || !std::isfinite(r.error)) ++row.failures;
      else errors.push_back(r.error);
    }
    fill_statistics(row, errors);
    row.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                   double acc = 0;
                                   for (const Sample& s : samples) {
                                     const auto r = parallel12r::inverse(m, s.target, method, ik);
                                     if (!r.solutions.empty()) acc += r.solutions.front().q_actuated.x();
                                   }
                                   g_sink = acc;
                                 }) /
                                 double(samples.size());
    rows.push_back(row);
  }
}

void jacobian_rows(const Model& m, const std::vector<Sample>& samples, const HarnessOptions& o,
                   std::vector<MethodRow>& rows) {
  struct Method {
    const char* name;
    double step;
    std::function<Matrix3d(const Vector3d&)> eval;
  };
  const std::vector<Method> methods = {
      {"analytic", 0, [&](const Vector3d& q) { return parallel12r::jacobian(m, q); }},
      {"central-difference", kCentralDifferenceStep,
       [&](const Vector3d& q) { return parallel12r::jacobian_central_difference(m, q, kCentralDifferenceStep); }},
      {"forward-difference", kForwardDifferenceStep,
       [&](const Vector3d& q) { return jacobian_forward_difference(m, q, kForwardDifferenceStep); }},
      {"complex-step", 1e-30, [&](const Vector3d& q) { return jacobian_complex_step(m, q); }},
  };
  std::vector<Matrix3d> reference;
  reference.reserve(samples.size());
  for (const Sample& s : samples) reference.push_back(reference_jacobian(m, s.q));
  for (const Method& method : methods) {
    MethodRow row = new_row("jacobian", method.name, "relative");
    if (method.step > 0) row.parameter = format_step(method.step);
    std::vector<double> errors;
    for (std::size_t i = 0; i < samples.size(); ++i)
      errors.push_back((method.eval(samples[i].q) - reference[i]).norm() / reference[i].norm());
    fill_statistics(row, errors);
    row.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                   double acc = 0;
                                   for (const Sample& s : samples) acc += method.eval(s.q)(0, 0);
                                   g_sink = acc;
                                 }) /
                                 double(samples.size());
    rows.push_back(row);
  }
}

void conditioning_rows(const std::vector<Sample>& samples, const HarnessOptions& o, std::vector<MethodRow>& rows) {
  const std::vector<std::pair<const char*, double (*)(const Matrix3d&)>> methods = {
      {"closed-form", &condition_number_closed_form},
      {"closed-form-fast", &condition_number_fast},
      {"svd", &condition_number_svd},
      {"normal-equations", &condition_number_normal_equations},
  };
  std::vector<double> reference;
  for (const Sample& s : samples) {
    const Vector3d sv = reference_singular_values(s.J);
    reference.push_back(sv(0) / sv(2));
  }
  for (const auto& [name, condition_number] : methods) {
    const auto& fn = condition_number;  // lambdas below cannot capture a structured binding under clang 14
    MethodRow row = new_row("conditioning", name, "relative");
    std::vector<double> errors;
    for (std::size_t i = 0; i < samples.size(); ++i) errors.push_back(std::abs(fn(samples[i].J) - reference[i]) / reference[i]);
    fill_statistics(row, errors);
    row.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                   double acc = 0;
                                   for (const Sample& s : samples) acc += fn(s.J);
                                   g_sink = acc;
                                 }) /
                                 double(samples.size());
    rows.push_back(row);
  }
}

// Count-based measures of a cube field: reachable volume, c < T volume and
// the c < T region's spans along x, z and its y-extent on the y > 0 side.
struct FieldMeasures {
  double reach_volume = 0, cond_volume = 0;
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  Vector3d hi = -lo;
  double seconds = 0;
};

FieldMeasures measure_field(const Model& m, int n, double threshold, int repeats) {
  FieldMeasures out;
  const double R = m.reach();
  const Grid full = Grid::box({-R, -R, -R}, {R, R, R}, {n, n, n});
  // In z slabs so the reference resolution needs little memory.
  const int slab = std::max(1, std::min(n, (1 << 20) / (n * n)));
  auto run = [&](bool measure) {
    for (int k0 = 0; k0 < n; k0 += slab) {
      FieldRequest r;
      r.grid = full;
      r.grid.dims[2] = std::min(slab, n - k0);
      r.grid.origin.z() = full.origin.z() + k0 * full.spacing.z();
      const std::optional<Field> f = compute_field(m, r);
      if (!measure) continue;
      const double cell = r.grid.spacing.prod();
      for (int k = 0; k < r.grid.dims[2]; ++k)
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const std::size_t s = r.grid.index(i, j, k);
            if (!f->reachable[s]) continue;
            out.reach_volume += cell;
            if (!(f->cond[s] < threshold)) continue;
            out.cond_volume += cell;
            const Vector3d p = r.grid.point(i, j, k);
            out.lo = out.lo.cwiseMin(p);
            out.hi = out.hi.cwiseMax(p);
          }
    }
  };
  run(true);
  out.seconds = repeats > 0 ? median_pass_seconds(repeats, [&] { run(false); }) : 0;
  return out;
}

void field_rows(const Model& m, const HarnessOptions& o, std::vector<MethodRow>& rows) {
  const double analytic = 4.0 / 3.0 * kPi * (std::pow(m.reach(), 3) - std::pow(m.inner_reach(), 3));
  const FieldMeasures ref = measure_field(m, o.field_reference_resolution, o.cond_threshold, 0);
  const std::string cond_name = "c<" + format_step(o.cond_threshold).substr(2);
  for (int n : o.field_resolutions) {
    const FieldMeasures f = measure_field(m, n, o.cond_threshold, n >= 128 ? std::min(o.repeats, 3) : o.repeats);
    const std::string parameter = "N=" + std::to_string(n);
    auto add = [&](const std::string& method, double error) {
      MethodRow row = new_row("field", method, "relative");
      row.parameter = parameter;
      row.samples = std::size_t(n) * n * n;
      row.seconds_per_evaluation = f.seconds;
      row.error_median = row.error_p99 = row.error_max = error;
      rows.push_back(row);
    };
    add("reach volume", std::abs(f.reach_volume - analytic) / analytic);
    add(cond_name + " volume", std::abs(f.cond_volume - ref.cond_volume) / ref.cond_volume);
    // Largest error of the x-span, z-span and y-extent (y > 0 side), relative to the reach.
    const double span_error = std::max({std::abs((f.hi.x() - f.lo.x()) - (ref.hi.x() - ref.lo.x())),
                                        std::abs((f.hi.z() - f.lo.z()) - (ref.hi.z() - ref.lo.z())),
                                        std::abs(f.hi.y() - ref.hi.y())}) /
                              m.reach();
    add(cond_name + " extents", span_error);
  }
}

}  // namespace

std::vector<MethodRow> run_method_harness(const Model& m, const HarnessOptions& o) {
  m.validate();
  if (o.samples < 10) throw std::invalid_argument("method harness: expected at least 10 samples, got " + std::to_string(o.samples));
  if (o.repeats < 1) throw std::invalid_argument("method harness: expected repeats >= 1");
  for (int n : o.field_resolutions)
    if (n < 2 || n > o.field_reference_resolution)
      throw std::invalid_argument("method harness: field resolutions must lie in 2..field_reference_resolution");

  if (o.progress) o.progress(0.0, "references");
  std::vector<Sample> samples;
  for (const Vector3d& p : workspace_targets(m, o.samples, o.seed)) {
    if (o.cancel && o.cancel->load()) return {};
    Sample s;
    s.target = p;
    s.ref = reference_ik(m, p);
    const auto& r = s.ref.branch[0] ? s.ref.branch[0] : s.ref.branch[1];
    if (!r) continue;  // on a singular set to rounding: no reference
    s.q = r->q_actuated;
    s.J = parallel12r::jacobian(m, s.q);
    samples.push_back(s);
  }
  std::vector<MethodRow> rows;
  auto stage = [&](double fraction, const char* name) {
    if (o.cancel && o.cancel->load()) return false;
    if (o.progress) o.progress(fraction, name);
    return true;
  };
  if (!stage(0.1, "inverse kinematics")) return rows;
  ik_rows(m, samples, o, rows);
  if (!stage(0.55, "Jacobians")) return rows;
  jacobian_rows(m, samples, o, rows);
  if (!stage(0.7, "condition numbers")) return rows;
  conditioning_rows(samples, o, rows);
  if (o.include_field && !o.field_resolutions.empty()) {
    if (!stage(0.8, "workspace fields")) return rows;
    field_rows(m, o, rows);
  }
  return rows;
}

}  // namespace linkscape::methods
