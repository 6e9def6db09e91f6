#include "core/mechanisms/described/model.h"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <regex>

#include "core/mechanisms/described/reader.h"

namespace linkscape::described {
using namespace reader;
namespace {

const char* const kPlatformCoordinates[6] = {"x", "y", "z", "rx", "ry", "rz"};

// Names the expressions define themselves (pi, deg, the copy index k and
// muparser's functions and constants): a parameter or extra of the same name
// would silently replace one.
const std::set<std::string>& reserved_names() {
  static const std::set<std::string> names = [] {
    std::set<std::string> n{"pi", "deg", "k"};
    const mu::Parser p;
    for (const auto& [name, f] : p.GetFunDef()) n.insert(name);
    for (const auto& [name, v] : p.GetConst()) n.insert(name);
    return n;
  }();
  return names;
}

// A whole number from lo to hi (lo >= 0), refused rather than wrapped when it
// is beyond an int.
int whole_number(const json& value, int lo, int hi, const std::string& where) {
  const bool in_range = value.is_number_unsigned() ? value.get<std::uint64_t>() <= std::uint64_t(hi)
                        : value.is_number_integer() && value.get<std::int64_t>() <= hi;
  if (!in_range || value.get<std::int64_t>() < lo)
    fail(where, "must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " +
                    value.dump());
  return int(value.get<std::int64_t>());
}

bool valid_name(const std::string& name) {
  static const std::regex pattern("[A-Za-z_][A-Za-z0-9_.]*");
  return std::regex_match(name, pattern);
}

// A parameter's or an extra's name: a variable of the expressions.
void check_variable_name(const std::string& name, const std::string& where) {
  if (!valid_name(name) || name.find('.') != std::string::npos)
    fail(where, "a parameter or extra name must be an identifier ([A-Za-z_][A-Za-z0-9_]*)");
  if (reserved_names().count(name))
    fail(where, "'" + name + "' is a name the expressions define themselves (reserved: " +
                    comma_list(reserved_names()) + ")");
}

// A chain link without a name is named by the joints at its ends.
void name_chain_links(Leg& leg) {
  for (LinkCapsule& c : leg.capsules) {
    if (c.on != LinkCapsule::On::Chain || !c.name.empty()) continue;
    std::string next = "anchor";
    for (std::size_t s = std::size_t(c.frame + 1); s < leg.steps.size(); ++s)
      if (leg.steps[s].kind != Step::Kind::Fixed) {
        next = leg.steps[s].joint;
        break;
      }
    c.name = "link " + (c.frame >= 0 ? leg.steps[std::size_t(c.frame)].joint : std::string("base anchor")) + "-" + next;
  }
}

// What the device's size measures, for reports and the fit's free lengths:
// the "size" expression as written, else the first leg's fixed steps (runs
// of steps between joints, each one transform, whose lengths the size
// sums) when each run holds one translation along one axis ("a + b"), else
// said in words.
std::string size_text(const json& doc) {
  auto text = [](const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); };
  if (doc.contains("size")) return text(doc.at("size"));
  const std::string words = "the first leg's link lengths";
  std::vector<std::string> terms;
  std::optional<std::string> run;  // the current run's term
  for (const json& step : doc.at("legs").at(0).at("chain")) {
    if (!step.is_object() || step.contains("joint")) {
      if (run) terms.push_back(*run);
      run.reset();
      continue;
    }
    if (!step.contains("translate")) continue;
    std::vector<std::string> along;
    for (const json& c : step.at("translate"))
      if (!(c.is_number() && c.get<double>() == 0)) along.push_back(text(c));
    if (along.empty()) continue;
    if (along.size() != 1 || run) return words;  // a length that is no sum of the terms
    run = along.front();
    if (run->size() > 1 && run->front() == '-') run->erase(0, 1);  // a length either way along its axis
  }
  if (run) terms.push_back(*run);
  std::string out;
  for (const std::string& t : terms) out += (out.empty() ? "" : " + ") + t;
  return out.empty() ? words : out;
}

}  // namespace

// The platform bodies' frames as functions of the extras: the JSON steps are
// kept and evaluated again per pose (they are few and short).
class ExpressionSet {
 public:
  ExpressionSet(std::map<std::string, double> parameters, std::vector<Extra> extras, std::vector<json> frames)
      : parameters_(std::move(parameters)), extras_(std::move(extras)), frames_(std::move(frames)) {}

  // Every pose asks, and the extras seldom change (fields hold them fixed):
  // the thread's last frames are reused for the same set and extras.
  const std::vector<Isometry3d>& evaluate(const Eigen::VectorXd& extra_values) const {
    thread_local struct {
      std::uint64_t id = 0;
      Eigen::VectorXd extras;
      std::vector<Isometry3d> frames;
    } last;
    if (last.id == id_ && last.extras.size() == extra_values.size() && last.extras == extra_values) return last.frames;
    Evaluator eval(parameters_);
    for (std::size_t e = 0; e < extras_.size(); ++e) eval.set_extra(extras_[e].name, extra_values(Eigen::Index(e)));
    std::vector<Isometry3d> out;
    for (std::size_t b = 0; b < frames_.size(); ++b)
      out.push_back(transform_steps(frames_[b], eval, "description.platforms[" + std::to_string(b) + "].frame"));
    last = {id_, extra_values, std::move(out)};
    return last.frames;
  }

 private:
  static inline std::atomic<std::uint64_t> next_id_{1};
  const std::uint64_t id_ = next_id_++;
  std::map<std::string, double> parameters_;
  std::vector<Extra> extras_;
  std::vector<json> frames_;
};

const std::vector<Isometry3d>& Model::platform_frames(const Eigen::VectorXd& extra_values) const {
  return frames->evaluate(extra_values);
}

int Model::driven() const {
  int n = 0;
  for (const TaskCoordinate& t : task) n += t.extra < 0;
  return n;
}

Model build_model(const std::string& description_json, const std::map<std::string, double>& parameters,
                  const std::map<std::string, Range>& limits_deg, const std::string& length_unit) {
  json doc;
  try {
    doc = parse_json_checked(description_json, kMaxPresetNesting);
  } catch (const json::exception& e) {
    fail("description", e.what());
  } catch (const std::invalid_argument& e) {
    fail("description", e.what());
  }
  const std::string top = "description";
  check_keys(doc,
             {"space", "task", "fixed", "extras", "home", "platforms", "legs", "parameter_info", "size", "box"}, top);
  if (parameters.size() > std::size_t(kMaxParameters))
    fail("parameters", "more than " + std::to_string(kMaxParameters) + " parameters");
  for (const auto& [name, v] : parameters) check_variable_name(name, "parameters." + name);
  for (const auto& [name, r] : limits_deg)
    if (!(r.lo < r.hi)) {
      std::ostringstream s;
      s << "needs lo < hi, got [" << r.lo << ", " << r.hi << "]";
      fail("actuator_limits_deg." + name, s.str());
    }

  // The legs' number, copies counted, before any is built.
  const json& legs = require(doc, "legs", top);
  if (!legs.is_array() || legs.empty()) fail(top + ".legs", "must be a non-empty list of legs");
  std::vector<int> copies(legs.size(), 1), firsts(legs.size(), 1);  // firsts: the number '#' stands for in copy 0
  for (std::size_t l = 0, count = 0; l < legs.size(); ++l) {
    const std::string where = top + ".legs[" + std::to_string(l) + "]";
    check_keys(legs[l], {"name", "copies", "first", "base", "chain", "platform", "anchor", "branch", "pattern"}, where);
    if (legs[l].contains("copies")) copies[l] = whole_number(legs[l].at("copies"), 1, kMaxLegs, where + ".copies");
    if (legs[l].contains("first")) firsts[l] = whole_number(legs[l].at("first"), 0, kMaxFirstNumber, where + ".first");
    count += std::size_t(copies[l]);
    if (count > std::size_t(kMaxLegs))
      fail(top + ".legs", "more than " + std::to_string(kMaxLegs) + " legs, copies counted (the format's limit)");
  }

  Model m;
  m.length_unit = length_unit;
  m.parameters = parameters;
  Evaluator eval(parameters);

  const std::string space = string_or(doc, "space", "spatial", top);
  if (space != "spatial" && space != "planar")
    fail(top + ".space", "must be \"spatial\" or \"planar\", got \"" + space + "\"");
  m.planar = space == "planar";

  // Extras first: the task may name them.
  if (doc.contains("extras")) {
    const json& extras = doc.at("extras");
    if (!extras.is_object()) fail(top + ".extras", "must be an object {name: {...}}");
    if (extras.size() > std::size_t(kMaxExtras))
      fail(top + ".extras", "more than " + std::to_string(kMaxExtras) + " extras (the format's limit)");
    for (const auto& [name, spec] : extras.items()) {
      const std::string where = top + ".extras." + name;
      check_variable_name(name, where);
      if (parameters.count(name)) fail(where, "'" + name + "' is a parameter's name");
      check_keys(spec, {"home", "range", "unit", "description"}, where);
      Extra e;
      e.name = name;
      e.home = eval.number(require(spec, "home", where), where + ".home");
      e.range = eval.range(require(spec, "range", where), where + ".range");
      e.unit = string_or(spec, "unit", length_unit, where);
      e.description = string_or(spec, "description", "", where);
      m.extras.push_back(e);
    }
  }

  // The task.
  const json& task = require(doc, "task", top);
  if (!task.is_array() || task.empty()) fail(top + ".task", "must be a non-empty list of coordinate names");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < task.size(); ++i) {
    const std::string where = top + ".task[" + std::to_string(i) + "]";
    if (!task[i].is_string()) fail(where, "must be a name");
    const std::string name = task[i].get<std::string>();
    if (!seen.insert(name).second) fail(where, "'" + name + "' is listed twice");
    TaskCoordinate t;
    t.name = name;
    for (int c = 0; c < 6; ++c)
      if (name == kPlatformCoordinates[c]) t.platform_coordinate = c;
    for (std::size_t e = 0; e < m.extras.size(); ++e)
      if (m.extras[e].name == name) t.extra = int(e);
    if (t.platform_coordinate < 0 && t.extra < 0)
      fail(where, "unknown coordinate '" + name + "' (known: x, y, z, rx, ry, rz and the extras)");
    if (t.platform_coordinate >= 0) m.free[t.platform_coordinate] = true;
    m.task.push_back(t);
  }
  for (const Extra& e : m.extras)
    if (!seen.count(e.name)) fail(top + ".extras." + e.name, "is not listed in the task");
  if (!m.free[0] || !m.free[1] || (!m.planar && !m.free[2]))
    fail(top + ".task", m.planar ? "a planar task needs x and y"
                                 : "a spatial task needs x, y and z: the task lists the platform's driven coordinates, "
                                   "and a device whose x and y follow the others (a 3-RPS, a 3-PRS) is not modelled");
  if (m.planar && (m.free[2] || m.free[3] || m.free[4]))
    fail(top + ".task", "a planar device moves in the xy plane: its task may list x, y, rz (and extras)");
  // Position first: generic code reads the task's x, y, z at indices 0..2.
  if (m.task[0].name != "x" || m.task[1].name != "y" || (!m.planar && m.task[2].name != "z"))
    fail(top + ".task", "must start with x, y" + std::string(m.planar ? "" : ", z"));

  if (doc.contains("fixed")) {
    const json& fixed = doc.at("fixed");
    if (!fixed.is_object()) fail(top + ".fixed", "must be an object {coordinate: value}");
    for (const auto& [name, value] : fixed.items()) {
      int c = -1;
      for (int k = 0; k < 6; ++k)
        if (name == kPlatformCoordinates[k]) c = k;
      if (c < 0) fail(top + ".fixed." + name, "unknown platform coordinate (known: x, y, z, rx, ry, rz)");
      if (m.free[c]) fail(top + ".fixed." + name, "is a task coordinate, so it cannot be fixed");
      m.fixed[c] = eval.number(value, top + ".fixed." + name);
    }
  }

  // Home.
  const json& home = require(doc, "home", top);
  if (!home.is_object()) fail(top + ".home", "must be an object {coordinate: value}");
  for (const auto& [name, v] : home.items())
    if (!seen.count(name)) fail(top + ".home." + name, "is not a task coordinate");
  m.home.resize(Eigen::Index(m.task.size()));
  for (std::size_t i = 0; i < m.task.size(); ++i) {
    const TaskCoordinate& t = m.task[i];
    if (home.contains(t.name)) m.home(Eigen::Index(i)) = eval.number(home.at(t.name), top + ".home." + t.name);
    else if (t.extra >= 0) m.home(Eigen::Index(i)) = m.extras[std::size_t(t.extra)].home;
    else fail(top + ".home", "missing a value for '" + t.name + "'");
  }

  // Platform bodies: their frames stay as JSON (they may depend on the extras).
  std::vector<json> frames;
  if (doc.contains("platforms")) {
    const json& platforms = doc.at("platforms");
    if (!platforms.is_array() || platforms.empty()) fail(top + ".platforms", "must be a non-empty list");
    if (platforms.size() > std::size_t(kMaxPlatforms))
      fail(top + ".platforms", "more than " + std::to_string(kMaxPlatforms) + " platform bodies (the format's limit)");
    for (std::size_t b = 0; b < platforms.size(); ++b) {
      const std::string where = top + ".platforms[" + std::to_string(b) + "]";
      check_keys(platforms[b], {"name", "frame"}, where);
      const std::string name = string_at(require(platforms[b], "name", where), where + ".name");
      for (const std::string& other : m.platform_names)
        if (other == name) fail(where, "platform '" + name + "' is listed twice");
      m.platform_names.push_back(name);
      frames.push_back(platforms[b].value("frame", json::array()));
    }
  } else {
    m.platform_names = {"platform"};
    frames = {json::array()};
  }
  m.frames = std::make_shared<ExpressionSet>(parameters, m.extras, frames);
  {
    Eigen::VectorXd extra_home(Eigen::Index(m.extras.size()));
    for (std::size_t e = 0; e < m.extras.size(); ++e) extra_home(Eigen::Index(e)) = m.extras[e].home;
    m.platform_frames(extra_home);  // throws naming the step if a frame is malformed
  }

  // Legs.
  std::set<std::string> joint_names, leg_names;
  for (std::size_t l = 0; l < legs.size(); ++l) {
    const json& spec = legs[l];
    const std::string leg_where = top + ".legs[" + std::to_string(l) + "]";
    for (int copy = 0; copy < copies[l]; ++copy) {
      eval.set_copy(copy, firsts[l]);
      Leg leg;
      leg.name = replace_hash(string_or(spec, "name", std::to_string(m.legs.size() + 1), leg_where), eval.hash_number());
      const std::string where = leg_where + " \"" + leg.name + "\"";
      if (!leg_names.insert(leg.name).second) fail(where, "leg name '" + leg.name + "' is used twice");
      leg.base = transform_steps(spec.value("base", json::array()), eval, where + ": base", &leg.capsules);
      leg.anchor = transform_steps(spec.value("anchor", json::array()), eval, where + ": anchor", &leg.capsules,
                                   LinkCapsule::On::Platform);
      for (LinkCapsule& c : leg.capsules)
        if (c.name.empty()) c.name = c.on == LinkCapsule::On::Base ? "base link" : "platform link";
      if (spec.contains("platform")) {
        const std::string body = string_at(spec.at("platform"), where + ": platform");
        leg.platform = -1;
        for (std::size_t b = 0; b < m.platform_names.size(); ++b)
          if (m.platform_names[b] == body) leg.platform = int(b);
        if (leg.platform < 0) fail(where + ": platform", "unknown platform body '" + body + "'");
      }
      const json& chain = require(spec, "chain", where);
      if (!chain.is_array() || chain.empty()) fail(where + ": chain", "must be a non-empty list of steps");
      Isometry3d pending = Isometry3d::Identity();
      bool have_pending = false;
      auto flush = [&] {
        if (!have_pending) return;
        Step s;
        s.transform = pending;
        leg.steps.push_back(s);
        pending = Isometry3d::Identity();
        have_pending = false;
      };
      for (std::size_t i = 0; i < chain.size(); ++i) {
        const json& step = chain[i];
        std::string at = where + ": chain[" + std::to_string(i) + "]";
        Isometry3d t;
        if (transform_step(step, eval, at, t, true)) {
          read_capsule(step, eval, at, pending, pending * t, LinkCapsule::On::Chain, int(leg.steps.size()) - 1,
                       leg.capsules);
          pending = pending * t;
          have_pending = true;
          continue;
        }
        if (!step.is_object() || !step.contains("joint"))
          fail(at, "expected a joint or a transform (translate, rx, ry, rz, rotate), got " + step.dump());
        const std::string type = string_at(step.at("joint"), at + ".joint");
        const std::string name = replace_hash(string_at(require(step, "name", at), at + ".name"), eval.hash_number());
        at += " (joint \"" + name + "\")";
        if (!valid_name(name)) fail(at, "a joint name must be an identifier");
        if (!joint_names.insert(name).second) fail(at, "joint name '" + name + "' is used twice");
        const bool actuated = bool_or(step, "actuated", false, at);
        if (type != "revolute" && type != "prismatic" && type != "universal" && type != "spherical")
          fail(at + ".joint", "unknown joint type '" + type + "' (known: revolute, prismatic, universal, spherical)");
        if (actuated && type != "revolute" && type != "prismatic")
          fail(at, "only revolute and prismatic joints can be actuated");
        flush();
        const std::size_t first_step = leg.steps.size();
        auto add = [&](Step::Kind kind, const Vector3d& axis, const std::string& step_name) {
          if (leg.variables + (kind == Step::Kind::Spherical ? 3 : 1) > kMaxLegVariables)
            fail(at, "the leg has more than " + std::to_string(kMaxLegVariables) +
                         " joint variables (the format's limit; a universal joint counts 2, a spherical 3)");
          Step s;
          s.kind = kind;
          s.axis = axis;
          s.name = step_name;
          s.joint = name;
          s.variable = leg.variables;
          leg.variables += kind == Step::Kind::Spherical ? 3 : 1;
          leg.spheres += kind == Step::Kind::Spherical;
          leg.steps.push_back(s);
        };
        if (type == "revolute" || type == "prismatic") {
          check_keys(step, {"joint", "name", "axis", "actuated", "range_deg", "range"}, at);
          const Vector3d axis = eval.unit_axis(require(step, "axis", at), at + ".axis");
          const bool prismatic = type == "prismatic";
          if (m.planar && !prismatic && std::abs(std::abs(axis.z()) - 1) > 1e-12)
            fail(at + ".axis", "a planar device's revolute axes must be [0, 0, 1] or [0, 0, -1]");
          if (m.planar && prismatic && std::abs(axis.z()) > 1e-12)
            fail(at + ".axis", "a planar device's prismatic axes must lie in the xy plane");
          add(prismatic ? Step::Kind::Prismatic : Step::Kind::Revolute, axis, name);
          Range range{-kPi, kPi};
          bool limited = false;
          const std::string range_key = prismatic ? "range" : "range_deg";
          if (step.contains(prismatic ? "range_deg" : "range"))
            fail(at, prismatic ? "a prismatic joint's travel is \"range\" (length unit)"
                               : "a revolute joint's travel is \"range_deg\" (degrees)");
          if (step.contains(range_key)) {
            range = eval.range(step.at(range_key), at + "." + range_key, prismatic ? 1.0 : kPi / 180);
            limited = true;
          } else if (actuated && prismatic) {
            fail(at, "an actuated prismatic joint needs its travel, \"range\": [lo, hi] (length unit)");
          }
          if (actuated) {
            if (!prismatic && limits_deg.count(name)) {
              range = {limits_deg.at(name).lo * kPi / 180, limits_deg.at(name).hi * kPi / 180};
              limited = true;
            }
            leg.steps.back().actuator = int(m.actuators.size());
            leg.actuators.push_back(int(m.actuators.size()));
            m.actuators.push_back({name, int(m.legs.size()), int(leg.steps.size()) - 1, prismatic, range, limited});
          }
        } else if (type == "universal") {
          check_keys(step, {"joint", "name", "axes", "ranges_deg"}, at);
          const json& axes = require(step, "axes", at);
          if (!axes.is_array() || axes.size() != 2) fail(at + ".axes", "must be two axes [[x, y, z], [x, y, z]]");
          const Vector3d a1 = eval.unit_axis(axes[0], at + ".axes[0]"), a2 = eval.unit_axis(axes[1], at + ".axes[1]");
          if (a1.cross(a2).norm() < 1e-6) fail(at + ".axes", "the two axes of a universal joint must not be parallel");
          if (m.planar) fail(at, "a planar device has no universal joints");
          add(Step::Kind::Revolute, a1, name + ".1");
          add(Step::Kind::Revolute, a2, name + ".2");
        } else if (type == "spherical") {
          check_keys(step, {"joint", "name", "cone"}, at);
          if (m.planar) fail(at, "a planar device has no spherical joints");
          add(Step::Kind::Spherical, Vector3d::UnitZ(), name);
        }
        read_joint_limits(step, type, actuated, eval, at, leg, first_step);
      }
      flush();
      name_chain_links(leg);
      if (spec.contains("pattern")) leg.pattern = string_at(spec.at("pattern"), where + ": pattern");
      if (leg.variables == 0) fail(where + ": chain", "has no joints");
      if (leg.actuators.size() != 1)
        fail(where + ": chain", leg.actuators.empty() ? "has no actuated joint (mark one \"actuated\": true)"
                                                      : "has more than one actuated joint (one per leg is supported)");

      // Branch rules.
      if (spec.contains("branch")) {
        const json rules = spec.at("branch").is_array() ? spec.at("branch") : json::array({spec.at("branch")});
        for (std::size_t r = 0; r < rules.size(); ++r) {
          const std::string at = where + ": branch" + (spec.at("branch").is_array() ? "[" + std::to_string(r) + "]" : "");
          check_keys(rules[r], {"triple", "angle", "along", "direction", "sign"}, at);
          BranchRule rule;
          auto step_of = [&](const json& n, bool allow_anchor) {
            const std::string name = replace_hash(string_at(n, at), eval.hash_number());
            if (allow_anchor && name == "anchor") return -2;
            for (std::size_t s = 0; s < leg.steps.size(); ++s)
              if (leg.steps[s].kind != Step::Kind::Fixed && (leg.steps[s].name == name || leg.steps[s].joint == name))
                return int(s);
            fail(at, "names no joint of this leg: '" + name + "'");
          };
          if (rules[r].contains("triple")) {
            const json& t = rules[r].at("triple");
            if (!t.is_array() || t.size() != 3) fail(at + ".triple", "must name three joints [A, B, C]");
            rule.kind = BranchRule::Kind::Triple;
            for (int i = 0; i < 3; ++i) rule.steps[std::size_t(i)] = step_of(t[std::size_t(i)], i == 2);
            if (leg.steps[std::size_t(rule.steps[0])].kind != Step::Kind::Revolute)
              fail(at + ".triple", "joint A must be revolute (its axis orients the turn)");
          } else if (rules[r].contains("angle")) {
            rule.kind = BranchRule::Kind::Angle;
            rule.steps[0] = step_of(rules[r].at("angle"), false);
            if (leg.steps[std::size_t(rule.steps[0])].kind != Step::Kind::Revolute)
              fail(at + ".angle", "must name a revolute joint");
          } else if (rules[r].contains("along")) {
            const json& t = rules[r].at("along");
            if (!t.is_array() || t.size() != 2) fail(at + ".along", "must name two joints [A, B]");
            rule.kind = BranchRule::Kind::Along;
            for (int i = 0; i < 2; ++i) rule.steps[std::size_t(i)] = step_of(t[std::size_t(i)], i == 1);
            if (!rules[r].contains("direction")) fail(at, "\"along\" needs a \"direction\" [x, y, z] (base frame)");
            rule.direction = eval.unit_axis(rules[r].at("direction"), at + ".direction");
          } else {
            fail(at, "needs \"triple\", \"angle\" or \"along\"");
          }
          if (rules[r].contains("sign")) {
            const double s = eval.number(rules[r].at("sign"), at + ".sign");
            if (s == 0) fail(at + ".sign", "must be positive or negative, not 0");
            rule.fixed_sign = s > 0 ? 1 : -1;
          } else {
            rule.free_index = m.free_rules++;
          }
          leg.rules.push_back(rule);
        }
      }
      m.legs.push_back(std::move(leg));
    }
  }
  eval.set_copy(0, 1);
  for (const auto& limit : limits_deg) {
    const std::string& name = limit.first;
    const Actuator* a = nullptr;
    for (const Actuator& x : m.actuators)
      if (x.name == name) a = &x;
    if (!a) {
      std::set<std::string> known;
      for (const Actuator& x : m.actuators) known.insert(x.name);
      fail("actuator_limits_deg." + name, "names no actuator of the description (actuators: " + comma_list(known) + ")");
    }
    if (a->prismatic)
      fail("actuator_limits_deg." + name, "is a prismatic actuator: its travel is the joint's \"range\" (length unit)");
  }
  if (m.free_rules > 12) fail(top + ".legs", "more than 12 free branch rules (4096 branches)");

  // The device's typical size.
  m.size_text = size_text(doc);
  if (doc.contains("size")) {
    m.size = eval.number(doc.at("size"), top + ".size");
  } else {
    m.size = 0;
    for (const Step& s : m.legs.front().steps)
      if (s.kind == Step::Kind::Fixed) m.size += s.transform.translation().norm();
  }
  if (!(m.size > 0)) fail(top + ".size", "the device's size must be positive (give \"size\" explicitly)");
  if (!std::isfinite(m.size))
    fail(top + ".size", "the device's size is not finite (a length far too large?)");

  if (doc.contains("box")) {
    const json& box = doc.at("box");
    check_keys(box, {"min", "max"}, top + ".box");
    const Vector3d lo = eval.vector(require(box, "min", top + ".box"), top + ".box.min");
    const Vector3d hi = eval.vector(require(box, "max", top + ".box"), top + ".box.max");
    if (!(lo.array() < hi.array()).all()) fail(top + ".box", "needs min < max in x, y and z");
    m.box = Eigen::AlignedBox3d(lo, hi);
  }

  // Parameter spans.
  if (doc.contains("parameter_info")) {
    const json& info = doc.at("parameter_info");
    if (!info.is_object()) fail(top + ".parameter_info", "must be an object {parameter: {...}}");
    for (const auto& [name, spec] : info.items()) {
      const std::string where = top + ".parameter_info." + name;
      if (!parameters.count(name)) fail(where, "is not a parameter");
      check_keys(spec, {"range", "unit", "description", "in_panel"}, where);
      Model::ParameterInfo p;
      if (spec.contains("range")) p.range = eval.range(spec.at("range"), where + ".range");
      p.unit = string_or(spec, "unit", "", where);
      p.description = string_or(spec, "description", "", where);
      p.in_panel = bool_or(spec, "in_panel", true, where);
      m.parameter_info[name] = p;
    }
  }
  return m;
}

std::string Leg::label() const {
  const bool says_leg = name.size() >= 3 && (name.compare(0, 3, "leg") == 0 || name.compare(0, 3, "Leg") == 0);
  return says_leg ? name : "leg " + name;
}

}  // namespace linkscape::described
