// Internal to the description reader (model.cpp, model_limits.cpp): the
// evaluator of a description's numbers and the checks of its JSON objects,
// each failure naming the place.
#pragma once

#include <muParser.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/json_checked.h"
#include "core/mechanisms/described/model.h"

namespace linkscape::described::reader {

using nlohmann::json;
using Eigen::Isometry3d;
using Eigen::Vector3d;

inline constexpr double kPi = 3.14159265358979323846;

[[noreturn]] inline void fail(const std::string& where, const std::string& what) {
  throw std::invalid_argument(where + ": " + what);
}

inline std::string replace_hash(std::string text, int number) {
  for (std::size_t at = text.find('#'); at != std::string::npos; at = text.find('#', at))
    text.replace(at, 1, std::to_string(number));
  return text;
}

inline std::string comma_list(const std::set<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

// Evaluates the numbers of a description: JSON numbers, or muparser
// expressions over the parameters, pi, deg, the copy index k and (platform
// frames only) the extras. Every name is a constant, so an expression cannot
// assign: it only computes a value.
class Evaluator {
 public:
  explicit Evaluator(const std::map<std::string, double>& parameters) : parameters_(parameters) {}

  // The leg copy being read: k = copy, and '#' in strings stands for first + copy.
  void set_copy(int copy, int first) {
    if (copy == copy_ && first == first_) return;
    copy_ = copy;
    first_ = first;
    parser_.reset();
  }
  void set_extra(const std::string& name, double value) {
    extra_values_[name] = value;
    parser_.reset();
  }
  int hash_number() const { return first_ + copy_; }

  double number(const json& value, const std::string& where) {
    if (value.is_number()) {
      const double v = value.get<double>();
      if (!std::isfinite(v)) fail(where, "must be finite");
      return v;
    }
    if (!value.is_string()) fail(where, "must be a number or an expression string, got " + value.dump());
    const std::string& written = value.get_ref<const std::string&>();
    if (written.size() > kMaxExpressionLength)
      fail(where, "an expression of " + std::to_string(written.size()) + " characters (at most " +
                      std::to_string(kMaxExpressionLength) + ")");
    for (std::size_t i = 0; i < written.size(); ++i)
      if (const auto c = static_cast<unsigned char>(written[i]); c < 0x20 || c == 0x7f) {
        char code[8];
        std::snprintf(code, sizeof code, "0x%02x", c);
        fail(where, "the expression holds the control character " + std::string(code) + " at " + std::to_string(i) +
                        " (an expression is one line of text)");
      }
    const std::string text = replace_hash(written, hash_number());
    try {
      mu::Parser& p = parser();
      p.SetExpr(text);
      const double v = p.Eval();
      if (p.GetNumResults() != 1)
        fail(where, "'" + text + "' is " + std::to_string(p.GetNumResults()) +
                        " expressions (a comma separates only a function's arguments)");
      if (!std::isfinite(v))
        fail(where, "'" + text + "' evaluates to " +
                        (std::isnan(v) ? std::string("no number (NaN: a square root or logarithm of a negative value?)")
                                       : std::string(v > 0 ? "+" : "-") + "infinity (a division by zero, or past 1e308?)"));
      return v;
    } catch (const mu::Parser::exception_type& e) {
      if (e.GetCode() == mu::ecUNEXPECTED_OPERATOR && e.GetToken() == "=")
        fail(where, "'" + text + "' assigns with '=': an expression only computes a value (compare with '==')");
      fail(where, "cannot evaluate '" + text + "': " + e.GetMsg() + known_names());
    }
  }

  Vector3d vector(const json& value, const std::string& where) {
    if (!value.is_array() || value.size() != 3) fail(where, "must be [x, y, z], got " + value.dump());
    return {number(value[0], where + "[0]"), number(value[1], where + "[1]"), number(value[2], where + "[2]")};
  }

  // [lo, hi] with lo < hi, each times `scale`.
  Range range(const json& value, const std::string& where, double scale = 1.0) {
    if (!value.is_array() || value.size() != 2) fail(where, "must be [lo, hi]");
    const Range r{scale * number(value[0], where + "[0]"), scale * number(value[1], where + "[1]")};
    if (!(r.lo < r.hi)) fail(where, "needs lo < hi");
    return r;
  }

  Vector3d unit_axis(const json& value, const std::string& where) {
    const Vector3d a = vector(value, where);
    const double n = a.norm();
    if (std::abs(n - 1) > 1e-9) {
      std::ostringstream s;
      s << "axis [" << a.x() << ", " << a.y() << ", " << a.z() << "] is not a unit vector (norm " << n << ")";
      fail(where, s.str());
    }
    return a / n;
  }

 private:
  // One parser for every number while the copy and the extras stay: the
  // names are its constants.
  mu::Parser& parser() {
    if (!parser_) {
      auto p = std::make_unique<mu::Parser>();
      p->DefineConst("pi", kPi);
      p->DefineConst("deg", kPi / 180);
      p->DefineConst("k", copy_);
      for (const auto& [name, v] : parameters_) p->DefineConst(name, v);
      for (const auto& [name, v] : extra_values_) p->DefineConst(name, v);
      parser_ = std::move(p);
    }
    return *parser_;
  }
  std::string known_names() const {
    std::string s = " (variables: pi, deg, k";
    for (const auto& [name, v] : parameters_) s += ", " + name;
    for (const auto& [name, v] : extra_values_) s += ", " + name;
    return s + ")";
  }
  std::map<std::string, double> parameters_;
  std::map<std::string, double> extra_values_;
  int copy_ = 0, first_ = 1;
  std::unique_ptr<mu::Parser> parser_;
};

inline void check_keys(const json& object, const std::set<std::string>& known, const std::string& where) {
  if (!object.is_object()) fail(where, "must be an object, got " + object.dump());
  for (const auto& [key, value] : object.items())
    if (!known.count(key)) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(where, "unknown key '" + key + "' (known: " + list + ")");
    }
}

inline const json& require(const json& object, const std::string& key, const std::string& where) {
  if (!object.contains(key)) fail(where, "missing key '" + key + "'");
  return object.at(key);
}

// An optional string or flag of an object, or its default.
inline std::string string_or(const json& object, const std::string& key, const std::string& fallback,
                      const std::string& where) {
  return object.contains(key) ? string_at(object.at(key), where + "." + key) : fallback;
}
inline bool bool_or(const json& object, const std::string& key, bool fallback, const std::string& where) {
  return object.contains(key) ? bool_at(object.at(key), where + "." + key) : fallback;
}

// A fixed transform step; returns false if `step` is not one.
// `link`: a translate may be a link, with "radius" and "link" (its name).
inline bool transform_step(const json& step, Evaluator& eval, const std::string& where, Isometry3d& out,
                           bool link = false) {
  out = Isometry3d::Identity();
  // One transform a step: {"rz": 30, "ry": 0} would be a guess at their order.
  if (step.is_object()) {
    std::string given;
    for (const char* key : {"translate", "rx", "ry", "rz", "rotate"})
      if (step.contains(key)) given += (given.empty() ? "" : ", ") + std::string(key);
    if (given.find(',') != std::string::npos)
      fail(where, "one transform a step, got " + given + ": write each as a step of its own, in the order they apply");
  }
  if (step.contains("translate")) {
    check_keys(step, link ? std::set<std::string>{"translate", "radius", "link"} : std::set<std::string>{"translate"},
               where);
    out.translation() = eval.vector(step.at("translate"), where + ".translate");
    return true;
  }
  for (int a = 0; a < 3; ++a) {
    const std::string key = std::string("r") + "xyz"[a];
    if (step.contains(key)) {
      check_keys(step, {key}, where);
      out.linear() = Eigen::AngleAxisd(eval.number(step.at(key), where + "." + key), Vector3d::Unit(a)).matrix();
      return true;
    }
  }
  if (step.contains("rotate")) {
    check_keys(step, {"rotate"}, where);
    const json& r = step.at("rotate");
    check_keys(r, {"axis", "angle"}, where + ".rotate");
    const Vector3d axis = eval.unit_axis(require(r, "axis", where + ".rotate"), where + ".rotate.axis");
    out.linear() =
        Eigen::AngleAxisd(eval.number(require(r, "angle", where + ".rotate"), where + ".rotate.angle"), axis).matrix();
    return true;
  }
  return false;
}

// A translate step's capsule, where it gives a "radius": the segment from
// before.translation() to after.translation() (model_limits.cpp).
void read_capsule(const json& step, Evaluator& eval, const std::string& where, const Isometry3d& before,
                  const Isometry3d& after, LinkCapsule::On on, int frame, std::vector<LinkCapsule>& out);

// A joint's limits ("range_deg" of a passive revolute, "ranges_deg" of a
// universal joint, "cone" of a spherical one), for the steps the joint just
// added to the leg (from `first_step`); refuses a limit no joint of its
// kind has (model_limits.cpp).
void read_joint_limits(const json& step, const std::string& type, bool actuated, Evaluator& eval,
                       const std::string& where, Leg& leg, std::size_t first_step);

// Where `capsules` is given, translate steps may be links (read_capsule).
inline Isometry3d transform_steps(const json& steps, Evaluator& eval, const std::string& where,
                                  std::vector<LinkCapsule>* capsules = nullptr,
                                  LinkCapsule::On on = LinkCapsule::On::Base) {
  if (!steps.is_array()) fail(where, "must be a list of steps, got " + steps.dump());
  Isometry3d t = Isometry3d::Identity();
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const std::string at = where + "[" + std::to_string(i) + "]";
    Isometry3d s;
    if (!transform_step(steps[i], eval, at, s, capsules != nullptr))
      fail(at, "expected a transform (translate, rx, ry, rz, rotate), got " + steps[i].dump());
    if (capsules) read_capsule(steps[i], eval, at, t, t * s, on, -1, *capsules);
    t = t * s;
  }
  return t;
}

}  // namespace linkscape::described::reader
