#include "core/haptics.h"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/preset.h"

namespace linkscape::haptics {
namespace {

using Eigen::VectorXd;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Three columns of J_p (two, for a planar device) count as dependent where
// |det| is below this times the product of their lengths (the sine of the
// angle the third makes with the plane of the other two, times the sine
// between those two): the vertex they define then lies beyond 1e12 times
// the forces along the columns, and double cannot place it.
constexpr double kRankTolerance = 1e-12;
// J_p M^-1 J_p^T counts as singular where its smallest eigenvalue is below
// this times its largest: the solver places that eigenvalue to about 1e4
// times less than itself, and the inertia would exceed 1e12 times the
// lightest direction's.
constexpr double kInertiaRankTolerance = 1e-12;

// The largest |F| over the polytope {F : |a_i . F| <= 1 for every column a_i
// of A} in D dimensions (3, or 2 for a planar device): a bounded convex
// polytope attains it at a vertex, where D independent constraints are
// active, so every D columns and every sign pattern are tried and the
// feasible points kept. +inf where no D columns are independent: A has rank
// < D and the polytope is unbounded along its null space.
template <int D>
double largest_vertex(const Eigen::Matrix<double, D, Eigen::Dynamic>& A) {
  using Square = Eigen::Matrix<double, D, D>;
  using Vector = Eigen::Matrix<double, D, 1>;
  const Eigen::Index n = A.cols();
  if (n < D) return kInf;
  std::array<Eigen::Index, D> pick;  // the columns tried, in increasing order
  for (int r = 0; r < D; ++r) pick[std::size_t(r)] = r;
  bool bounded = false;
  double best = 0;
  while (true) {
    Square M;
    double scale = 1;
    for (int r = 0; r < D; ++r) {
      M.row(r) = A.col(pick[std::size_t(r)]).transpose();
      scale *= A.col(pick[std::size_t(r)]).norm();
    }
    if (std::abs(M.determinant()) > kRankTolerance * scale) {
      bounded = true;
      const Eigen::PartialPivLU<Square> lu(M);
      for (int signs = 0; signs < 1 << (D - 1); ++signs) {  // -F is the same vertex mirrored
        Vector rhs;
        for (int r = 0; r < D; ++r) rhs(r) = r > 0 && (signs >> (r - 1)) & 1 ? -1.0 : 1.0;
        const Vector F = lu.solve(rhs);
        if ((A.transpose() * F).cwiseAbs().maxCoeff() <= 1 + 1e-9) best = std::max(best, F.norm());
      }
    }
    int r = D - 1;  // the next combination
    while (r >= 0 && pick[std::size_t(r)] == n - D + r) --r;
    if (r < 0) break;
    ++pick[std::size_t(r)];
    for (int k = r + 1; k < D; ++k) pick[std::size_t(k)] = pick[std::size_t(k - 1)] + 1;
  }
  return bounded ? best : kInf;
}

// The measures of J_p, the D position rows of J in metres per motor radian.
template <int D>
Measures measures_of(const Eigen::Matrix<double, D, Eigen::Dynamic>& Jp, const DeviceData& data,
                     TorqueRating rating) {
  const Eigen::Index n = Jp.cols();
  Eigen::Matrix<double, D, Eigen::Dynamic> A(D, n);  // a_i = J_p e_i / tau_i: actuator i is within its limit iff |a_i . F| <= 1
  Measures m;
  m.force_iso_N = kInf;
  double resolution_m = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Rating& r = data.actuators[std::size_t(i)];
    const double tau = rating == TorqueRating::Peak ? r.peak_torque_Nm : r.continuous_torque_Nm;
    const double column = Jp.col(i).norm();
    A.col(i) = Jp.col(i) / tau;
    // Every F with |F| <= tau_i / |J_p e_i| keeps |a_i . F| <= 1, and F along
    // J_p e_i reaches the limit: the smallest over the actuators is the force
    // available in every direction.
    m.force_iso_N = std::min(m.force_iso_N, tau / column);
    resolution_m = std::max(resolution_m, 2 * std::numbers::pi / r.encoder_counts_per_rev * column);
  }
  m.resolution_mm = 1e3 * resolution_m;
  m.force_max_N = largest_vertex<D>(A);
  if (data.has_inertia()) {
    // Endpoint acceleration a = J_p M^-1 J_p^T F (rotors only, at rest):
    // the apparent mass along u is 1 / (u^T J_p M^-1 J_p^T u), largest
    // along the eigenvector of the smallest eigenvalue.
    Eigen::Matrix<double, D, D> inverse_mass = Eigen::Matrix<double, D, D>::Zero();
    for (Eigen::Index i = 0; i < n; ++i)
      inverse_mass += Jp.col(i) * Jp.col(i).transpose() / *data.actuators[std::size_t(i)].rotor_inertia_kgm2;
    const auto lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>>(inverse_mass, Eigen::EigenvaluesOnly).eigenvalues();
    m.inertia_kg = lambda(0) > kInertiaRankTolerance * lambda(D - 1) ? 1.0 / lambda(0) : kInf;
  }
  return m;
}

// A prismatic actuator's default drive: a capstan of 1 cm radius.
constexpr double kDefaultLead_m = 2 * std::numbers::pi * 0.01;

std::string number_text(double v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

double DeviceData::metres_per_motor_radian(std::size_t i) const {
  const Rating& r = actuators.at(i);
  return r.lead_m_per_rev ? *r.lead_m_per_rev / (2 * std::numbers::pi) : metres_per_length_unit;
}

bool DeviceData::has_inertia() const {
  if (actuators.empty()) return false;
  for (const Rating& r : actuators)
    if (!r.rotor_inertia_kgm2) return false;
  return true;
}

TorqueRating parse_torque_rating(const std::string& text) {
  if (text == "continuous") return TorqueRating::Continuous;
  if (text == "peak") return TorqueRating::Peak;
  throw std::invalid_argument("torque rating must be continuous or peak, got '" + text + "'");
}

const char* to_string(TorqueRating rating) { return rating == TorqueRating::Peak ? "peak" : "continuous"; }

const std::vector<std::string>& length_units() {
  static const std::vector<std::string> units{"mm", "cm", "m", "in"};
  return units;
}

bool is_length_unit(const std::string& unit) {
  return std::find(length_units().begin(), length_units().end(), unit) != length_units().end();
}

double metres_per(const std::string& length_unit) {
  if (length_unit == "m") return 1.0;
  if (length_unit == "cm") return 0.01;
  if (length_unit == "mm") return 0.001;
  if (length_unit == "in") return 0.0254;
  throw std::invalid_argument("haptic measures need the preset's length_unit to be m, cm, mm or in (forces are in N), "
                              "got '" + length_unit + "'");
}

Rating default_rating(bool prismatic) {
  Rating r;
  r.continuous_torque_Nm = 0.18;
  r.peak_torque_Nm = 1.0;
  r.encoder_counts_per_rev = 2000;  // 500 lines, quadrature
  r.rotor_inertia_kgm2 = 1.4e-5;
  if (prismatic) r.lead_m_per_rev = kDefaultLead_m;
  return r;
}

namespace {

// The ratings at each actuator as the preset gives them (per-actuator entries
// over "all"), or Linkscape's defaults where it gives none.
std::vector<ActuatorRating> given_ratings(const ActuatorDataSpec& spec, const MechanismInfo& info,
                                          const std::function<bool(const Quantity&)>& prismatic) {
  std::vector<ActuatorRating> out;
  for (const Quantity& a : info.actuators) {
    ActuatorRating r = spec.all;
    if (!spec.given) {
      const Rating d = default_rating(prismatic(a));
      r = {d.peak_torque_Nm, d.continuous_torque_Nm, d.encoder_counts_per_rev, d.rotor_inertia_kgm2, d.lead_m_per_rev,
           std::nullopt};
    }
    if (const auto own = spec.per_actuator.find(a.name); own != spec.per_actuator.end())
      for (const MotorParameter& p : motor_parameters())
        if (own->second.*(p.field)) r.*(p.field) = own->second.*(p.field);
    out.push_back(r);
  }
  return out;
}

}  // namespace

DeviceData device_data(const Preset& preset, const MechanismInfo& info) {
  DeviceData d;
  d.metres_per_length_unit = metres_per(info.length_unit);
  d.position_rows = info.plane_z ? 2 : 3;
  // Angles are in rad; any other actuator is a slide in the length unit.
  auto prismatic = [](const Quantity& a) { return a.unit != "rad"; };
  const ActuatorDataSpec& spec = preset.actuator_data;
  for (const auto& [name, rating] : spec.per_actuator) {
    bool known = false;
    std::string names;
    for (const Quantity& a : info.actuators) {
      known = known || a.name == name;
      names += (names.empty() ? "" : ", ") + a.name;
    }
    if (!known)
      throw std::invalid_argument("preset actuator_data: '" + name + "' is not an actuator of " + info.name +
                                  " (actuators: " + names + "; or 'all', 'source')");
  }
  std::vector<ActuatorRating> ratings = given_ratings(spec, info, prismatic);
  // Ratings given as parameters (--param, sessions, sweeps) hold for every actuator.
  std::string from_parameters;
  for (const MotorParameter& p : motor_parameters())
    if (const auto it = preset.parameters.find(p.name); it != preset.parameters.end()) {
      check_rating(std::string("parameter ") + p.name, it->second);
      for (ActuatorRating& r : ratings) r.*(p.field) = it->second;
      from_parameters += std::string(from_parameters.empty() ? "" : ", ") + p.name + " " + number_text(it->second);
    }
  // A lead for every actuator (--param lead_m_per_rev=...) needs a slide to drive.
  if (preset.parameters.count("lead_m_per_rev") &&
      std::none_of(info.actuators.begin(), info.actuators.end(), [&](const Quantity& a) { return prismatic(a); }))
    throw std::invalid_argument("parameter lead_m_per_rev is for prismatic actuators; " + info.name +
                                "'s are all revolute");
  for (std::size_t i = 0; i < info.actuators.size(); ++i) {
    const Quantity& a = info.actuators[i];
    const ActuatorRating& given = ratings[i];
    auto value = [&](std::optional<double> ActuatorRating::*field, const char* key, bool required) {
      if (given.*field || !required) return given.*field;
      throw std::invalid_argument("preset actuator_data: no " + std::string(key) + " for actuator " + a.name +
                                  " (give it under 'all' or '" + a.name + "')");
    };
    // The joint's side of the reduction: torques and counts times n, inertia times n^2.
    const double n = given.gear_ratio.value_or(1.0);
    Rating r;
    r.peak_torque_Nm = n * *value(&ActuatorRating::peak_torque_Nm, "peak_torque_Nm", true);
    r.continuous_torque_Nm = n * *value(&ActuatorRating::continuous_torque_Nm, "continuous_torque_Nm", true);
    r.encoder_counts_per_rev = n * *value(&ActuatorRating::encoder_counts_per_rev, "encoder_counts_per_rev", true);
    if (const auto inertia = value(&ActuatorRating::rotor_inertia_kgm2, "rotor_inertia_kgm2", false))
      r.rotor_inertia_kgm2 = n * n * *inertia;
    if (prismatic(a)) r.lead_m_per_rev = value(&ActuatorRating::lead_m_per_rev, "lead_m_per_rev", true);
    else if (const auto own = spec.per_actuator.find(a.name);
             own != spec.per_actuator.end() && own->second.lead_m_per_rev)
      throw std::invalid_argument("preset actuator_data: lead_m_per_rev is for prismatic actuators; " + a.name +
                                  " is revolute");
    if (r.continuous_torque_Nm > r.peak_torque_Nm)
      throw std::invalid_argument("actuator ratings: continuous_torque_Nm of " + a.name + " exceeds its peak_torque_Nm");
    d.actuators.push_back(r);
  }
  if (!spec.given) {
    bool slides = false;
    for (const Quantity& a : info.actuators) slides = slides || prismatic(a);
    const Rating r = default_rating();
    d.source = "Linkscape defaults (the preset has no actuator_data): " + number_text(r.continuous_torque_Nm) +
               " N m continuous, " + number_text(r.peak_torque_Nm) + " N m peak, " +
               number_text(r.encoder_counts_per_rev) + " counts/rev, rotor " + number_text(*r.rotor_inertia_kgm2) +
               " kg m^2" + (slides ? ", slides driven by a capstan of 1 cm radius" : "");
    d.defaults = from_parameters.empty();
  } else {
    d.source = spec.source.empty() ? "preset actuator_data" : spec.source;
    d.defaults = spec.source.rfind("default", 0) == 0 && from_parameters.empty();
  }
  if (!from_parameters.empty()) d.source += "; set as parameters: " + from_parameters;
  return d;
}

Measures measures(const Eigen::MatrixXd& J, const DeviceData& data, TorqueRating rating) {
  const Eigen::Index n = J.cols(), rows = data.position_rows;
  if (J.rows() < rows || n != Eigen::Index(data.actuators.size()))
    throw std::invalid_argument("haptic measures: J is " + std::to_string(J.rows()) + "x" + std::to_string(n) +
                                ", expected " + std::to_string(rows) + " or more rows and one column per actuator (" +
                                std::to_string(data.actuators.size()) + ")");
  // Position rows in metres per motor radian: then tau = J_p^T F is in N m for F in N.
  Eigen::MatrixXd Jp = J.topRows(rows);
  for (Eigen::Index i = 0; i < n; ++i) Jp.col(i) *= data.metres_per_motor_radian(std::size_t(i));
  if (rows == 2) return measures_of<2>(Jp, data, rating);
  return measures_of<3>(Jp, data, rating);
}

const std::vector<FieldInfo>& all_field_infos() {
  static const std::vector<FieldInfo> infos = {{"force_iso", "isotropic force", "N", true},
                                               {"force_max", "largest force", "N", true},
                                               {"resolution", "resolution", "mm", false},
                                               {"inertia", "reflected inertia", "kg", false}};
  return infos;
}

std::vector<FieldInfo> field_infos(const DeviceData& data) {
  std::vector<FieldInfo> out = all_field_infos();
  if (!data.has_inertia()) out.pop_back();
  return out;
}

bool is_haptic_field(const std::string& name) {
  for (const FieldInfo& f : all_field_infos())
    if (f.name == name) return true;
  return false;
}

bool add_fields(Field& f, const Mechanism& mechanism, const DeviceData& data, TorqueRating rating,
                const VectorXd& fixed_task, const IkOptions& ik_options, int threads, const FieldProgress& progress) {
  const MechanismInfo& info = mechanism.info();
  // The measures are the design branch's: solve that one only.
  IkOptions ik = ik_options;
  ik.branch = ik.branch.value_or(0);
  if (fixed_task.size() != Eigen::Index(info.task.size()))
    throw std::invalid_argument("haptic fields: the fixed task needs " + std::to_string(info.task.size()) +
                                " coordinates, got " + std::to_string(fixed_task.size()));
  const std::vector<FieldInfo> infos = field_infos(data);
  const std::size_t n = f.grid.size();
  std::vector<SampleArray<float>*> out;
  for (const FieldInfo& fi : infos) {
    auto existing = std::find_if(f.extras.begin(), f.extras.end(), [&](const auto& a) { return a.name == fi.name; });
    if (existing == f.extras.end()) existing = f.extras.insert(f.extras.end(), Field::NamedArray{});
    existing->name = fi.name;
    existing->title = fi.title;
    existing->unit = fi.unit;
    existing->description = std::string(to_string(rating)) + " torque; actuator data: " + data.source;
    existing->values.resize(n);
  }
  for (const FieldInfo& fi : infos)  // pointers after every insertion
    for (auto& a : f.extras)
      if (a.name == fi.name) out.push_back(&a.values);
  const bool with_inertia = data.has_inertia();
  const int branch = *ik.branch;

  constexpr std::int64_t kChunk = 256;
  const std::int64_t chunks = (std::int64_t(n) + kChunk - 1) / kChunk;
  const std::int64_t report_every = std::max<std::int64_t>(1, chunks / 200);
  std::atomic<std::int64_t> done{0};
  const int team = threads > 0 ? threads : omp_get_max_threads();
  const std::int64_t nx = f.grid.dims[0], nxy = nx * f.grid.dims[1];
  std::atomic<bool> failed{false};
  std::string failure;
#pragma omp parallel for schedule(dynamic, 2) num_threads(team)
  for (std::int64_t c = 0; c < chunks; ++c) {
    if ((progress.cancel && progress.cancel->load(std::memory_order_relaxed)) || failed.load()) continue;
    VectorXd x = fixed_task;
    const std::int64_t end = std::min<std::int64_t>(std::int64_t(n), (c + 1) * kChunk);
    try {
      for (std::int64_t idx = c * kChunk; idx < end; ++idx) {
        float values[4] = {0.0f, 0.0f, INFINITY, INFINITY};  // fail every criterion
        if (f.reachable[std::size_t(idx)]) {
          x.head<3>() = f.grid.point(int(idx % nx), int((idx / nx) % f.grid.dims[1]), int(idx / nxy));
          // A planar device's field is its plane's, extruded along z.
          if (info.plane_z) x(2) = *info.plane_z;
          const IkResult r = mechanism.inverse(x, ik);
          for (const IkSolution& s : r.solutions) {
            if (s.branch != branch || s.status != Status::Ok) continue;
            const Measures m = measures(mechanism.jacobian(s.q, x), data, rating);
            values[0] = float(m.force_iso_N);
            values[1] = float(m.force_max_N);
            values[2] = float(m.resolution_mm);
            values[3] = with_inertia ? float(*m.inertia_kg) : INFINITY;
            break;
          }
        }
        for (std::size_t a = 0; a < out.size(); ++a) (*out[a])[std::size_t(idx)] = values[a];
      }
    } catch (const std::exception& e) {
#pragma omp critical(haptic_failure)
      if (!failed.exchange(true)) failure = e.what();
    }
    const std::int64_t k = done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (progress.report && k % report_every == 0) progress.report(double(k) / double(chunks));
  }
  if (failed) throw std::invalid_argument("haptic fields: " + failure);
  if (progress.cancel && progress.cancel->load()) return false;
  if (progress.report) progress.report(1.0);
  return true;
}

std::optional<Field> sample_field(const Mechanism& mechanism, const Grid& grid, const VectorXd& fixed_task,
                                  const IkOptions& ik, int threads, const FieldProgress& progress,
                                  const DeviceData* data, TorqueRating rating) {
  // The haptic pass (generic IK per sample) takes most of the time.
  constexpr double kKernelShare = 0.1;
  FieldProgress kernel = progress, extra = progress;
  if (progress.report && data) {
    kernel.report = [&](double f) { progress.report(kKernelShare * f); };
    extra.report = [&](double f) { progress.report(kKernelShare + (1 - kKernelShare) * f); };
  }
  std::optional<Field> field = mechanism.compute_field(grid, fixed_task, ik, threads, kernel);
  if (!field || !data) return field;
  if (!add_fields(*field, mechanism, *data, rating, fixed_task, ik, threads, extra)) return std::nullopt;
  return field;
}

}  // namespace linkscape::haptics
