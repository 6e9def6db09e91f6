// The free variables of a fit or sweep from the command line's lists
// (core/fit.h: variables, size_terms).
#include <algorithm>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/fit.h"

namespace linkscape::fit {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

std::vector<std::string> size_terms(const MechanismInfo& info) {
  std::vector<std::string> out;
  std::stringstream terms(info.size_description);
  for (std::string term; std::getline(terms, term, '+');) {
    term.erase(0, term.find_first_not_of(' '));
    term.erase(term.find_last_not_of(' ') + 1);
    out.push_back(term);
  }
  return out;
}

std::string Variable::name() const {
  std::string out;
  for (const std::string& p : parameters) out += (out.empty() ? "" : "=") + p;
  return out;
}

std::vector<Variable> variables(const Mechanism& mechanism, const std::vector<std::string>& free,
                                const std::vector<std::string>& equal, const std::vector<std::string>& bounds,
                                const std::string& command) {
  // The linkage's parameters, then the motor ratings (core/actuator_data.h),
  // which have no range of their own: they need --bounds.
  std::vector<Quantity> described = mechanism.info().parameters;
  for (const MotorParameter& p : motor_parameters()) {
    Quantity q;
    q.name = p.name;
    q.unit = p.unit;
    q.range = {-kInf, kInf};
    q.in_panel = false;
    described.push_back(q);
  }
  auto find = [&](const std::string& name) -> const Quantity& {
    for (const Quantity& q : described)
      if (q.name == name) return q;
    std::string known, motors;
    for (const Quantity& q : described)
      if (q.in_panel) known += (known.empty() ? "" : ", ") + q.name;
    for (const MotorParameter& p : motor_parameters()) motors += (motors.empty() ? "" : ", ") + std::string(p.name);
    throw std::invalid_argument(command + ": unknown parameter '" + name + "' for " + mechanism.info().name +
                                " (design parameters: " + known + "; motor ratings: " + motors + ")");
  };
  auto split = [](const std::string& text) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    for (std::string part; std::getline(ss, part, ',');) out.push_back(part);
    return out;
  };
  std::vector<std::string> names;
  for (const std::string& f : free)
    for (const std::string& n : split(f)) names.push_back(find(n).name);
  if (free.empty())
    for (const Quantity& q : described)
      if (q.in_panel) names.push_back(q.name);
  std::vector<Variable> out;
  std::set<std::string> taken;
  for (const std::string& group : equal) {
    Variable v;
    for (const std::string& n : split(group)) {
      find(n);
      if (!taken.insert(n).second) throw std::invalid_argument(command + ": parameter '" + n + "' is in two --equal groups");
      v.parameters.push_back(n);
    }
    if (v.parameters.size() < 2) throw std::invalid_argument(command + ": --equal expects two or more parameters, got '" + group + "'");
    out.push_back(v);
  }
  for (const std::string& n : names)
    if (taken.insert(n).second) out.push_back({{n}, 0, 0});
  for (Variable& v : out) {
    v.lo = -kInf;
    v.hi = kInf;
    for (const std::string& n : v.parameters) {
      const Quantity& q = find(n);
      v.lo = std::max(v.lo, q.range.lo);
      v.hi = std::min(v.hi, q.range.hi);
    }
  }
  std::set<std::string> bounded;  // variables given bounds
  for (const std::string& b : bounds) {
    const auto eq = b.find('='), colon = b.find(':');
    if (eq == std::string::npos || colon == std::string::npos || colon < eq)
      throw std::invalid_argument(command + ": --bounds expects NAME=lo:hi, got '" + b + "'");
    const std::string name = b.substr(0, eq);
    const double lo = parse_number_or_throw(b.substr(eq + 1, colon - eq - 1), "--bounds " + name + " lower bound");
    const double hi = parse_number_or_throw(b.substr(colon + 1), "--bounds " + name + " upper bound");
    find(name);
    auto it = std::find_if(out.begin(), out.end(), [&](const Variable& v) {
      return std::count(v.parameters.begin(), v.parameters.end(), name) > 0;
    });
    if (it == out.end()) throw std::invalid_argument(command + ": --bounds names '" + name + "', which is not free");
    if (!bounded.insert(it->name()).second)
      throw std::invalid_argument(command + ": --bounds given twice for " + it->name() + " (again as '" + b + "')");
    it->lo = lo;
    it->hi = hi;
  }
  for (const Variable& v : out) {
    const auto motors = std::count_if(v.parameters.begin(), v.parameters.end(),
                                      [](const std::string& n) { return motor_parameter(n) != nullptr; });
    if (motors > 0 && motors < std::ptrdiff_t(v.parameters.size()))
      throw std::invalid_argument(command + ": --equal cannot hold a motor rating equal to a length (" + v.name() + ")");
    if (motors > 0 && !(std::isfinite(v.lo) && std::isfinite(v.hi)))
      throw std::invalid_argument(command + ": the motor rating " + v.name() + " needs --bounds " + v.parameters.front() +
                                  "=LO:HI (it has no range of its own)");
  }
  return out;
}

}  // namespace linkscape::fit
