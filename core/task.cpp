#include "core/task.h"

#include <omp.h>

#include <algorithm>
#include <cctype>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"

namespace linkscape::task {

using Eigen::Vector3d;

namespace {

// Conditioning measures are bounded from above by a number > 1, forces from
// below and resolution and inertia from above by a positive number, and an
// extra field (a margin to a stop) from below by a positive number.
void check_bound(const Criterion& c) {
  const bool larger_is_better = c.extra || c.measure == "force_iso" || c.measure == "force_max";
  if (c.above != larger_is_better)
    throw std::invalid_argument("criterion '" + c.text + "': " + c.measure + " is bounded " +
                                (larger_is_better ? "from below (" + c.measure + ">VALUE)"
                                                  : "from above (" + c.measure + "<VALUE)"));
  if (c.extra && !(c.threshold > 0))
    throw std::invalid_argument("criterion '" + c.text + "': the threshold must be positive (a pose beyond a stop "
                                "is already out of limits, so reach keeps " + c.measure + " at 0 or more)");
  if (!c.haptic() && !c.extra && !(c.threshold > 1))
    throw std::invalid_argument("criterion '" + c.text + "': no pose meets it (condition numbers are at least 1)");
  if (!(c.threshold > 0))
    throw std::invalid_argument("criterion '" + c.text + "': no pose meets it (the threshold must be positive)");
}

}  // namespace

std::string quoting_hint(const std::string& text) {
  if (text.empty() || text.find_first_of("<>") != std::string::npos || text == "reach" || text == "reachable") return "";
  // Forces and the margins to a stop are bounded from below (task.h's examples).
  const std::string example = text + (text.rfind("force", 0) == 0 ? ">1"
                                      : text == "joint_margin"     ? ">5"
                                      : text == "clearance"        ? ">0.5"
                                                                   : "<3");
  return "; quote the criterion: '" + example + "' (unquoted, a shell takes the < or > for a redirection, drops "
         "it and the number, and may create a file named after the number)";
}

std::vector<std::string> split_criteria(const std::string& text) {
  // Spaces about a comparison belong to the criterion: 'cond < 3' is cond<3.
  std::string joined;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool space = std::isspace(static_cast<unsigned char>(text[i]));
    const auto comparison = [](char c) { return c == '<' || c == '>' || c == '='; };
    if (space && !joined.empty() && comparison(joined.back())) continue;
    if (space) {
      std::size_t next = text.find_first_not_of(" \t\n\r\f\v", i);
      if (next != std::string::npos && comparison(text[next])) continue;
    }
    joined += text[i];
  }
  std::vector<std::string> out;
  std::string part;
  for (const char c : joined + " ") {
    if (c == ',' || c == ';' || std::isspace(static_cast<unsigned char>(c))) {
      if (!part.empty()) out.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  return out;
}

std::vector<Criterion> parse_criteria(const std::string& text) {
  std::vector<Criterion> out;
  for (const std::string& part : split_criteria(text)) out.push_back(parse_criterion(part));
  return out;
}

std::string criterion_unit(const Criterion& c, const std::string& length_unit) {
  if (c.reach() || c.measure == "clearance") return length_unit;
  if (c.measure == "joint_margin") return "deg";
  for (const haptics::FieldInfo& f : haptics::all_field_infos())
    if (f.name == c.measure) return f.unit;
  return "";
}

Criterion parse_criterion(const std::string& text) {
  Criterion c;
  c.text = text;
  if (text == "reach" || text == "reachable") {
    c.measure = "reach";
    return c;
  }
  const auto op = text.find_first_of("<>");
  if (op == std::string::npos || op == 0)
    throw std::invalid_argument("criterion '" + text +
                                "': expected reach or NAME<VALUE / NAME>VALUE, e.g. cond<3, force_iso>2, "
                                "resolution<0.5, inertia<0.2" + quoting_hint(text));
  c.measure = text.substr(0, op);
  if (c.measure == "reach" || c.measure == "reachable")
    throw std::invalid_argument("criterion '" + text + "': reach takes no threshold (write reach: the pose is "
                                "reached within the travel)");
  c.above = text[op] == '>';
  std::size_t number = op + 1;
  if (number < text.size() && text[number] == '=') ++number;  // <= and >= read as < and >
  const std::optional<double> v = parse_number(text.substr(number));
  if (!v || !std::isfinite(*v))
    throw std::invalid_argument("criterion '" + text + "': the threshold must be a finite number");
  c.threshold = *v;
  // A device's other measures are checked when it is known (resolve).
  if (c.measure == "cond" || c.haptic()) check_bound(c);
  return c;
}

Criterion resolve(const Criterion& c, const MechanismInfo& info, const haptics::DeviceData* data) {
  Criterion out = c;
  if (c.reach() || c.measure == "cond") return out;
  std::string known = "reach, cond";
  for (std::size_t k = 0; k < info.measures.size(); ++k) {
    if (info.measures[k].name == c.measure) {
      check_bound(c);
      if (k > 1)
        throw std::invalid_argument("criterion '" + c.text + "': fields hold the first two measures of a device only");
      out.measure_index = int(k);
      return out;
    }
    if (info.measures[k].name != "cond") known += ", " + info.measures[k].name;
  }
  for (const NamedItem& f : info.extra_fields) {
    if (f.name == c.measure) {
      out.extra = true;
      out.measure_index = -1;  // no conditioning measure: whatever indexes them refuses it
      check_bound(out);
      return out;
    }
    known += ", " + f.name;
  }
  if (c.haptic()) {
    if (!data) throw std::invalid_argument("criterion '" + c.text + "': haptic measures need the preset's actuator data");
    if (c.measure == "inertia" && !data->has_inertia())
      throw std::invalid_argument("criterion '" + c.text + "': the preset gives no rotor_inertia_kgm2 for every actuator");
    return out;
  }
  for (const haptics::FieldInfo& f : haptics::all_field_infos()) known += ", " + f.name;
  throw std::invalid_argument("criterion '" + c.text + "': unknown measure '" + c.measure + "' for " + info.name +
                              " (known: " + known + ")");
}

// ---- Task volumes -------------------------------------------------------------------

Eigen::AlignedBox3d TaskVolume::bounds(const Vector3d& c) const { return {c - size / 2, c + size / 2}; }

bool TaskVolume::contains(const Vector3d& p, const Vector3d& c) const {
  if (shape == Shape::Sphere) return (p - c).norm() <= diameter() / 2;
  return ((p - c).cwiseAbs().array() <= size.array() / 2).all();
}

double TaskVolume::volume() const {
  return shape == Shape::Sphere ? std::numbers::pi / 6 * std::pow(diameter(), 3) : size.prod();
}

std::string to_text(const TaskVolume& t) {
  std::string text = t.shape == Shape::Sphere
                         ? "sphere:diameter=" + format_number(t.diameter())
                         : "box:size=" + format_number(t.size.x()) + "," + format_number(t.size.y()) + "," +
                               format_number(t.size.z());
  if (t.centre)
    text += ",centre=" + format_number(t.centre->x()) + "," + format_number(t.centre->y()) + "," +
            format_number(t.centre->z());
  return text;
}

namespace {

// "shape:key=v[,v...],..." as the shape and the key=v[,v...] pairs: a part
// without '=' continues the previous key's list. `what` names the text in errors.
std::pair<std::string, std::map<std::string, std::vector<double>>> shape_and_keys(const std::string& what,
                                                                                  const std::string& text,
                                                                                  const std::string& usage) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw std::invalid_argument(usage);
  std::map<std::string, std::vector<double>> keys;
  std::string key, part;
  std::stringstream parts(text.substr(colon + 1));
  while (std::getline(parts, part, ',')) {
    std::string value = part;
    if (const auto eq = part.find('='); eq != std::string::npos) {
      key = part.substr(0, eq);
      value = part.substr(eq + 1);
      if (keys.count(key)) throw std::invalid_argument(usage + " ('" + key + "' given twice)");
      keys[key];
    }
    if (key.empty()) throw std::invalid_argument(usage);
    const std::optional<double> v = parse_number(value);
    if (!v || !std::isfinite(*v))
      throw std::invalid_argument(what + " '" + text + "': " + key + " expects finite numbers, got '" + value + "'");
    keys[key].push_back(*v);
  }
  return {text.substr(0, colon), keys};
}

// The point of key `name` (three numbers), taken out of `keys`; nullopt where absent.
std::optional<Vector3d> take_point(std::map<std::string, std::vector<double>>& keys, const std::string& name,
                                   const std::string& usage) {
  const auto it = keys.find(name);
  if (it == keys.end()) return std::nullopt;
  if (it->second.size() != 3) throw std::invalid_argument(usage + " (" + name + " expects 3 values)");
  const Vector3d p(it->second[0], it->second[1], it->second[2]);
  keys.erase(it);
  return p;
}

}  // namespace

bool CentreRegion::contains(const Vector3d& p) const {
  return shape == Shape::Sphere ? (p - centre).norm() <= radius : box.contains(p);
}

Eigen::AlignedBox3d CentreRegion::bounds() const {
  return shape == Shape::Sphere ? Eigen::AlignedBox3d(centre.array() - radius, centre.array() + radius) : box;
}

std::string to_text(const CentreRegion& r) {
  auto point = [](const Vector3d& p) { return format_number(p.x()) + "," + format_number(p.y()) + "," + format_number(p.z()); };
  return r.shape == Shape::Sphere ? "sphere:centre=" + point(r.centre) + ",radius=" + format_number(r.radius)
                                  : "box:min=" + point(r.box.min()) + ",max=" + point(r.box.max());
}

CentreRegion parse_centre_region(const std::string& text) {
  const std::string usage = "centre region '" + text + "': expected box:min=x,y,z,max=x,y,z or "
                            "sphere:centre=x,y,z,radius=r";
  auto [shape, keys] = shape_and_keys("centre region", text, usage);
  CentreRegion r;
  r.text = text;
  if (shape == "box") {
    const auto lo = take_point(keys, "min", usage), hi = take_point(keys, "max", usage);
    if (!lo || !hi) throw std::invalid_argument(usage + " (give min and max)");
    if (!(lo->array() <= hi->array()).all())
      throw std::invalid_argument(usage + " (min must not exceed max on any axis)");
    r.box = Eigen::AlignedBox3d(*lo, *hi);
  } else if (shape == "sphere") {
    r.shape = Shape::Sphere;
    const auto c = take_point(keys, "centre", usage);
    const auto radius = keys.find("radius");
    if (!c || radius == keys.end() || radius->second.size() != 1)
      throw std::invalid_argument(usage + " (give centre and one radius)");
    r.centre = *c;
    r.radius = radius->second[0];
    keys.erase(radius);
    if (!(r.radius > 0)) throw std::invalid_argument(usage + " (the radius must be positive)");
  } else {
    throw std::invalid_argument(usage + " (unknown shape '" + shape + "')");
  }
  if (!keys.empty()) throw std::invalid_argument(usage + " (unknown key '" + keys.begin()->first + "')");
  return r;
}

TaskVolume parse_task(const std::string& text) {
  const std::string usage = "task '" + text + "': expected sphere:diameter=D, sphere:radius=R or box:size=X,Y,Z (or "
                            "box:size=S), optionally followed by ,centre=x,y,z";
  auto [shape, keys] = shape_and_keys("task", text, usage);
  TaskVolume t;
  t.text = text;
  if (shape == "sphere") t.shape = Shape::Sphere;
  else if (shape == "box") t.shape = Shape::Box;
  else throw std::invalid_argument(usage + " (unknown shape '" + shape + "')");
  auto take = [&](const std::string& name, std::size_t min_count, std::size_t max_count) -> std::optional<std::vector<double>> {
    const auto it = keys.find(name);
    if (it == keys.end()) return std::nullopt;
    if (it->second.size() < min_count || it->second.size() > max_count)
      throw std::invalid_argument("task '" + text + "': " + name + " expects " +
                                  (min_count == max_count ? std::to_string(min_count) : "1 or 3") + " values");
    std::vector<double> v = it->second;
    keys.erase(it);
    return v;
  };
  if (const auto c = take("centre", 3, 3)) t.centre = Vector3d((*c)[0], (*c)[1], (*c)[2]);
  if (t.shape == Shape::Sphere) {
    const auto d = take("diameter", 1, 1), r = take("radius", 1, 1);
    if (d.has_value() == r.has_value()) throw std::invalid_argument(usage + " (give the diameter or the radius)");
    t.size = Vector3d::Constant(d ? (*d)[0] : 2 * (*r)[0]);
  } else {
    const auto v = take("size", 1, 3);
    if (!v || v->size() == 2) throw std::invalid_argument(usage + " (give size=S or size=X,Y,Z)");
    t.size = v->size() == 1 ? Vector3d::Constant((*v)[0]) : Vector3d((*v)[0], (*v)[1], (*v)[2]);
  }
  if (!keys.empty()) throw std::invalid_argument(usage + " (unknown key '" + keys.begin()->first + "')");
  if (!(t.size.array() > 0).all())
    throw std::invalid_argument("task '" + text + "' is empty: its size must be positive");
  return t;
}

// ---- What is sampled -------------------------------------------------------------------

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Whether `value` of the criterion's measure meets it.
bool meets(const Criterion& c, double value) { return c.above ? value > c.threshold : value < c.threshold; }

// The value of a resolved criterion's measure at sample s of a field.
double value_of(const Field& f, const Criterion& c, std::size_t s) {
  if (c.reach()) return f.reach_margin[s];
  if (c.haptic() || c.extra) return f.extra(c.measure)->values[s];
  return c.measure_index == 0 ? f.cond[s] : f.cond_orientation[s];
}

bool needs_haptics(const std::vector<Criterion>& criteria) {
  return std::any_of(criteria.begin(), criteria.end(), [](const Criterion& c) { return c.haptic(); });
}

// The device's field at the one sample `p`: its extra fields as fields show
// them (they have no point-wise call).
Field field_at(const Device& device, const Vector3d& p) {
  Grid grid;
  grid.origin = p - grid.spacing / 2;  // the cell centred on p
  std::optional<Field> f = device.mechanism->compute_field(grid, device.fixed_task, device.ik, 1, {});
  if (!f) throw std::logic_error("a one-sample field was cancelled with no way to cancel it");
  for (const NamedItem& e : device.mechanism->info().extra_fields)
    if (!f->extra(e.name)) throw std::logic_error(e.name + " is listed by the device but missing from its field");
  return std::move(*f);
}

}  // namespace

std::vector<Criterion> resolve(const Device& device, const std::vector<Criterion>& criteria) {
  std::vector<Criterion> out;
  for (const Criterion& c : criteria)
    out.push_back(resolve(c, device.mechanism->info(), device.data ? &*device.data : nullptr));
  return out;
}

PointValues evaluate_point(const Device& device, const std::vector<Criterion>& criteria, const Vector3d& p) {
  const Mechanism& m = *device.mechanism;
  Eigen::VectorXd x = device.fixed_task;
  x.head<3>() = p;
  if (const std::optional<double> plane = m.info().plane_z) x(2) = *plane;  // a planar task is its section
  IkOptions one_branch = device.ik;  // the criteria are the design branch's: solve that one only
  one_branch.branch = device.ik.branch.value_or(0);
  const int branch = *one_branch.branch;
  const IkResult ik = m.inverse(x, one_branch);
  const IkSolution* solution = nullptr;
  for (const IkSolution& s : ik.solutions)
    if (s.branch == branch && s.status == Status::Ok) solution = &s;
  Measures measures;
  std::optional<haptics::Measures> h;
  std::optional<Field> extras;
  if (solution) {
    measures = m.measures(solution->q, x);
    if (needs_haptics(criteria)) h = haptics::measures(m.jacobian(solution->q, x), *device.data, device.torque);
    if (std::any_of(criteria.begin(), criteria.end(), [](const Criterion& c) { return c.extra; }))
      extras = field_at(device, p);
  }
  PointValues out;
  out.reachable = solution != nullptr;
  out.meets = out.reachable;
  for (const Criterion& c : criteria) {
    double v;
    if (c.reach()) v = m.reach_margin(x, branch);
    else if (!solution) v = c.above ? 0.0 : kInf;
    else if (c.haptic())
      v = c.measure == "force_iso"    ? h->force_iso_N
          : c.measure == "force_max"  ? h->force_max_N
          : c.measure == "resolution" ? h->resolution_mm
                                      : *h->inertia_kg;
    else if (c.extra) v = value_of(*extras, c, 0);
    else v = std::size_t(c.measure_index) < measures.values.size() ? measures.values[std::size_t(c.measure_index)] : kInf;
    out.values.push_back(v);
    if (!c.reach()) out.meets = out.meets && meets(c, v);
  }
  return out;
}

std::vector<std::uint8_t> good_mask(const Field& field, const std::vector<Criterion>& criteria) {
  for (const Criterion& c : criteria) {
    if ((c.haptic() || c.extra) && !field.extra(c.measure))
      throw std::invalid_argument("criterion '" + c.text + "': the field has no " + c.measure + " array");
    if (!c.reach() && !c.haptic() && !c.extra && c.measure_index == 1 && field.cond_orientation.size() != field.grid.size())
      throw std::invalid_argument("criterion '" + c.text + "': the field has no second condition array");
  }
  std::vector<std::uint8_t> good(field.grid.size());
  for (std::size_t s = 0; s < good.size(); ++s) {
    bool ok = field.reachable[s] != 0;
    for (const Criterion& c : criteria)
      if (ok && !c.reach()) ok = meets(c, value_of(field, c, s));
    good[s] = ok;
  }
  return good;
}

std::optional<Field> sample(const Device& device, const std::vector<Criterion>& criteria, const Grid& grid,
                            const FieldProgress& progress) {
  const bool haptic = needs_haptics(criteria);
  if (haptic && !device.data) throw std::invalid_argument("haptic criteria need the preset's actuator data");
  return haptics::sample_field(*device.mechanism, grid, device.fixed_task, device.ik, device.threads, progress,
                               haptic ? &*device.data : nullptr, device.torque);
}

// ---- A task at a place ----------------------------------------------------------------

std::string samples_text(int counted, int samples) {
  double percent = samples > 0 ? std::round(10000.0 * counted / samples) / 100 : 0.0;  // two decimals
  if (counted < samples) percent = std::min(percent, 99.99);
  if (counted > 0) percent = std::max(percent, 0.01);
  std::ostringstream s;
  s << counted << " of " << samples << " samples (" << std::setprecision(4) << percent << " %)";
  return s.str();
}

std::string verdict_text(const TaskReport& r) {
  const std::string at = " (evaluated at resolution " + std::to_string(r.resolution) + ")";
  if (r.meets()) return "meets every criterion at all " + std::to_string(r.samples) + " samples" + at;
  const int meeting = r.samples - r.failing;
  return std::string("fails: ") + (meeting > 0 ? "only " : "") + samples_text(meeting, r.samples) + " meet every criterion" + at;
}

double CriterionReport::margin() const {
  if (criterion.reach()) return worst;
  return criterion.above ? worst - criterion.threshold : criterion.threshold - worst;
}

namespace {

// The task evaluated at `at`; with `give_up_on_failure`, nullopt as soon as
// a sample fails (the surface, where failures usually are, first).
std::optional<TaskReport> evaluate_task(const Device& device, const std::vector<Criterion>& criteria,
                                        const TaskVolume& task, const Vector3d& at, int resolution,
                                        bool give_up_on_failure) {
  if (resolution < 2 || resolution > kMaxTaskResolution)
    throw std::invalid_argument("task evaluation: resolution must be 2 to " + std::to_string(kMaxTaskResolution) +
                                ", got " + std::to_string(resolution));
  // A planar device's task is its section by the plane: one layer, centred on the plane.
  const std::optional<double> plane = device.mechanism->info().plane_z;
  const bool flat = plane.has_value();
  const Vector3d centre = flat ? Vector3d(at.x(), at.y(), *plane) : at;
  const Eigen::AlignedBox3d bounds = task.bounds(centre);
  const Vector3d extent = bounds.sizes();
  const double longest = flat ? extent.head<2>().maxCoeff() : extent.maxCoeff();
  std::array<int, 3> dims{};
  for (int k = 0; k < 3; ++k) dims[k] = std::max(2, int(std::lround(resolution * extent(k) / longest)));
  if (flat) dims[2] = 1;
  const Grid grid = Grid::box(bounds.min(), bounds.max(), dims);
  std::vector<Vector3d> points;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        if (task.contains(grid.point(i, j, k), centre)) points.push_back(grid.point(i, j, k));
  const std::size_t interior = points.size();
  if (task.shape == Shape::Sphere && flat) {
    // The disc's rim, evenly.
    const int n = std::max(64, 8 * resolution);
    const double r = task.diameter() / 2;
    for (int k = 0; k < n; ++k) {
      const double phi = 2 * std::numbers::pi * k / n;
      points.push_back(centre + r * Vector3d(std::cos(phi), std::sin(phi), 0));
    }
  } else if (task.shape == Shape::Sphere) {
    // Fibonacci points: nearly even spacing, no clustering at poles.
    const int n = std::max(64, resolution * resolution);
    const double r = task.diameter() / 2;
    for (int k = 0; k < n; ++k) {
      const double z = 1 - (2 * k + 1.0) / n, rho = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
      points.push_back(centre + r * Vector3d(rho * std::cos(phi), rho * std::sin(phi), z));
    }
  } else {
    // Each face: its cell centres of the grid, on the face (a rectangle's
    // edges: the faces across x and y, one layer thick).
    for (int axis = 0; axis < (flat ? 2 : 3); ++axis)
      for (double side : {-0.5, 0.5}) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        for (int j = 0; j < dims[b]; ++j)
          for (int i = 0; i < dims[a]; ++i) {
            Vector3d p = centre;
            p(axis) += side * extent(axis);
            p(a) = bounds.min()(a) + (i + 0.5) * grid.spacing(a);
            p(b) = bounds.min()(b) + (j + 0.5) * grid.spacing(b);
            points.push_back(p);
          }
      }
  }
  std::vector<PointValues> values(points.size());
  std::atomic<bool> failed{false}, fails_task{false};
  std::string failure;
#pragma omp parallel for schedule(dynamic, 16) num_threads(device.threads > 0 ? device.threads : omp_get_max_threads())
  for (std::int64_t k = 0; k < std::int64_t(points.size()); ++k) {
    if (failed || fails_task) continue;
    const std::size_t i = points.size() - 1 - std::size_t(k);  // the surface first
    try {
      values[i] = evaluate_point(device, criteria, points[i]);
      if (give_up_on_failure && !values[i].meets) fails_task = true;
    } catch (const std::exception& e) {
#pragma omp critical(task_failure)
      if (!failed.exchange(true)) failure = e.what();
    }
  }
  if (failed) throw std::invalid_argument("task evaluation: " + failure);
  if (fails_task) return std::nullopt;

  TaskReport r;
  r.centre = centre;
  r.resolution = resolution;
  r.samples = int(points.size());
  std::size_t meeting = 0;
  Vector3d failing_sum = Vector3d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (values[i].meets) {
      meeting += i < interior;
      continue;
    }
    ++r.failing;
    failing_sum += points[i];
    r.failing_bounds.extend(points[i]);
  }
  r.fraction = interior ? double(meeting) / double(interior) : 0.0;
  if (r.failing) r.failing_centroid = failing_sum / r.failing;
  for (std::size_t c = 0; c < criteria.size(); ++c) {
    CriterionReport cr;
    cr.criterion = criteria[c];
    const bool larger_is_worse = !criteria[c].reach() && !criteria[c].above;
    cr.worst = larger_is_worse ? -kInf : kInf;
    std::size_t meeting_c = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double v = values[i].values[c];
      if (larger_is_worse ? v > cr.worst : v < cr.worst) cr.worst = v, cr.worst_point = points[i];
      const bool ok = criteria[c].reach() ? values[i].reachable : values[i].reachable && meets(criteria[c], v);
      if (i < interior) meeting_c += ok;
      cr.failing += !ok;
    }
    cr.fraction = interior ? double(meeting_c) / double(interior) : 0.0;
    r.criteria.push_back(cr);
  }
  return r;
}

}  // namespace

TaskReport evaluate(const Device& device, const std::vector<Criterion>& criteria, const TaskVolume& task,
                    const Vector3d& at, int resolution) {
  return *evaluate_task(device, criteria, task, at, resolution, false);
}

std::optional<TaskReport> evaluate_if_meets(const Device& device, const std::vector<Criterion>& criteria,
                                            const TaskVolume& task, const Vector3d& at, int resolution) {
  return evaluate_task(device, criteria, task, at, resolution, true);
}

}  // namespace linkscape::task
