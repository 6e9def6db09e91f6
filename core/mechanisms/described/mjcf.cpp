#include "core/mechanisms/described/mjcf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/haptics.h"
#include "core/mechanism.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/model.h"

namespace linkscape::described {
namespace {

constexpr const char* kCoordinateNames[6] = {"x", "y", "z", "rx", "ry", "rz"};

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v == 0.0 ? 0.0 : v);  // no "-0"
  return buffer;
}

std::string escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Writes the nested bodies of the MJCF tree, with lengths in metres.
class Writer {
 public:
  explicit Writer(double metres) : metres_(metres) {}

  std::string vector(const Eigen::Vector3d& v) const {
    return number(v.x() * metres_) + " " + number(v.y() * metres_) + " " + number(v.z() * metres_);
  }
  static std::string direction(const Eigen::Vector3d& v) {
    return number(v.x()) + " " + number(v.y()) + " " + number(v.z());
  }
  std::string frame(const Eigen::Isometry3d& t) const {
    const Eigen::Quaterniond q(t.rotation());
    return "pos=\"" + vector(t.translation()) + "\" quat=\"" + number(q.w()) + " " + number(q.x()) + " " +
           number(q.y()) + " " + number(q.z()) + "\"";
  }

  void open(const std::string& name, const Eigen::Isometry3d& frame_in_parent) {
    line("<body name=\"" + escaped(name) + "\" " + frame(frame_in_parent) + ">");
    ++depth_;
  }
  void close() {
    --depth_;
    line("</body>");
  }
  // radius > 0: the description's (length unit), else the class's.
  void capsule(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const char* cls, double radius = 0) {
    if ((to - from).norm() * metres_ < 1e-9) return;
    line(std::string("<geom class=\"") + cls + "\" type=\"capsule\" fromto=\"" + vector(from) + " " + vector(to) +
         "\"" + (radius > 0 ? " size=\"" + number(radius * metres_) + "\"" : std::string()) + "/>");
  }
  // The description's links held in one frame (`on`, for a chain link its frame's step).
  void links(const Leg& leg, LinkCapsule::On on, int frame, const Eigen::Isometry3d& placed, const char* cls) {
    for (const LinkCapsule& c : leg.capsules)
      if (c.on == on && (on != LinkCapsule::On::Chain || c.frame == frame)) capsule(placed * c.a, placed * c.b, cls, c.radius);
  }
  void ball(const char* cls) { line(std::string("<geom class=\"") + cls + "\" type=\"sphere\"/>"); }
  void line(const std::string& text) { out_ << std::string(2 * depth_ + 4, ' ') << text << "\n"; }
  std::string text() const { return out_.str(); }

 private:
  double metres_;
  int depth_ = 0;
  std::ostringstream out_;
};

bool has_links(const Leg& leg, LinkCapsule::On on, int frame) {
  for (const LinkCapsule& c : leg.capsules)
    if (c.on == on && (on != LinkCapsule::On::Chain || c.frame == frame)) return true;
  return false;
}

Eigen::Isometry3d rotation(const Eigen::Vector3d& axis, double angle) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return t;
}

Eigen::Isometry3d translation(const Eigen::Vector3d& v) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = v;
  return t;
}

// The platform: a body per coordinate (position, then rz, ry, rx), each
// hinge or slide with its home value as `ref`, then the platform bodies.
void write_platform(Writer& w, const Model& model, const std::array<double, 6>& home,
                    const std::vector<Eigen::Isometry3d>& bodies, double metres) {
  w.open("platform_position", translation(Eigen::Vector3d(home[0], home[1], home[2])));
  for (int c = 0; c < 3; ++c)
    if (model.free[c])
      w.line("<joint name=\"" + mjcf_platform_joint(kCoordinateNames[c]) + "\" type=\"slide\" axis=\"" +
             Writer::direction(Eigen::Vector3d::Unit(c)) + "\" ref=\"" + number(home[c] * metres) + "\"/>");
  for (const int c : {5, 4, 3}) {  // R = Rz Ry Rx
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(c - 3);
    w.open(std::string("platform_") + kCoordinateNames[c], rotation(axis, home[c]));
    if (model.free[c])
      w.line("<joint name=\"" + mjcf_platform_joint(kCoordinateNames[c]) + "\" type=\"hinge\" axis=\"" +
             Writer::direction(axis) + "\" ref=\"" + number(home[c]) + "\"/>");
  }
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    w.open(model.platform_names[b], bodies[b]);
    w.ball("platform");
    for (const Leg& leg : model.legs)
      if (leg.platform == int(b)) {
        if (has_links(leg, LinkCapsule::On::Platform, -1)) w.links(leg, LinkCapsule::On::Platform, -1, Eigen::Isometry3d::Identity(), "platform");
        else w.capsule(Eigen::Vector3d::Zero(), leg.anchor.translation(), "platform");
      }
    w.close();
  }
  for (int k = 0; k < 4; ++k) w.close();
}

// A revolute's limit as a hinge's range: the turn of it nearest the joint's
// value at home (MuJoCo's range is literal, Linkscape's any turn of it).
std::string hinge_range(const Range& r, double home) {
  const double turn = 2 * M_PI * std::round((home - 0.5 * (r.lo + r.hi)) / (2 * M_PI));
  return " range=\"" + number(r.lo + turn) + " " + number(r.hi + turn) + "\"";
}

// A leg as nested bodies from the world, one per joint, at its home state;
// a slide's `ref` in metres, a hinge's in radians. The description's links
// are capsules of their radii; a leg without them is drawn with the default.
void write_leg(Writer& w, const Model& model, const Leg& leg, const LegState& home, double metres,
               const std::vector<double>& armature) {
  int open = 0, sphere = 0, frame = -1;
  Eigen::Isometry3d t = leg.base;  // in the current body
  bool in_world = true;            // the base steps are the frame, not links
  w.links(leg, LinkCapsule::On::Base, -1, Eigen::Isometry3d::Identity(), "link");
  w.links(leg, LinkCapsule::On::Chain, -1, leg.base, "link");
  for (std::size_t s = 0; s < leg.steps.size(); ++s) {
    const Step& step = leg.steps[s];
    if (step.kind == Step::Kind::Fixed) {
      if (!in_world && !has_links(leg, LinkCapsule::On::Chain, frame))
        w.capsule(t.translation(), (t * step.transform).translation(), "link");
      t = t * step.transform;
      continue;
    }
    const double value = home.values[step.variable];  // a spherical step's slot is unused
    std::string joint = "<joint name=\"" + escaped(step.name) + "\" ";
    switch (step.kind) {
      case Step::Kind::Revolute:
        w.open(step.name, t * rotation(step.axis, value));
        joint += "type=\"hinge\" axis=\"" + Writer::direction(step.axis) + "\" ref=\"" + number(value) + "\"";
        break;
      case Step::Kind::Prismatic:
        w.open(step.name, t * translation(step.axis * value));
        joint += "type=\"slide\" axis=\"" + Writer::direction(step.axis) + "\" ref=\"" + number(value * metres) + "\"";
        break;
      default: {  // spherical: the home rotation is the body's, the ball turns from it
        Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
        r.linear() = home.spheres[std::size_t(sphere++)];
        w.open(step.name, t * r);
        joint += "type=\"ball\"";
      }
    }
    if (step.actuator >= 0 && model.actuators[std::size_t(step.actuator)].limited) {
      const Range range = model.actuators[std::size_t(step.actuator)].range;
      const double scale = step.kind == Step::Kind::Prismatic ? metres : 1.0;
      joint += " range=\"" + number(range.lo * scale) + " " + number(range.hi * scale) + "\"";
    }
    if (step.actuator >= 0) joint += " armature=\"" + number(armature[std::size_t(step.actuator)]) + "\"";
    // A passive revolute's limit; a ball's cone has no MuJoCo counterpart
    // (a ball's range bounds its whole rotation from home, twist included).
    for (const JointLimit& l : leg.limits)
      if (l.kind == JointLimit::Kind::Range && l.step == int(s)) joint += hinge_range(l.range, value);
    w.line(joint + "/>");
    w.ball("joint");
    w.links(leg, LinkCapsule::On::Chain, int(s), Eigen::Isometry3d::Identity(), "link");
    frame = int(s);
    ++open;
    in_world = false;
    t = Eigen::Isometry3d::Identity();
  }
  w.open(mjcf_leg_end(leg.name), t);
  w.close();
  for (int k = 0; k < open; ++k) w.close();
}

// Each actuator's motor rotor reflected to its joint (MJCF armature: kg m²,
// or kg through a prismatic actuator's lead): the preset's rating, else
// Linkscape's default one. Without it the actuated joints have only their
// links' small inertia, and MuJoCo's loop constraints drive them unstably
// (docs/model-export.md).
std::vector<double> armatures(const haptics::DeviceData& data) {
  std::vector<double> out;
  for (std::size_t a = 0; a < data.actuators.size(); ++a) {
    const haptics::Rating& r = data.actuators[a];
    const bool prismatic = r.lead_m_per_rev.has_value();
    const double inertia = r.rotor_inertia_kgm2.value_or(*haptics::default_rating(prismatic).rotor_inertia_kgm2);
    out.push_back(prismatic ? inertia * std::pow(2 * M_PI / *r.lead_m_per_rev, 2) : inertia);
  }
  return out;
}

// Each actuator's peak at its joint (MJCF ctrlrange: N m, or N through a
// prismatic actuator's lead) as the haptic measures take the ratings: the
// gear ratio and ratings given as --param included. None where the preset
// rates no motor (Linkscape's default rating is no device's).
std::optional<double> control_limit(const Preset& preset, const haptics::Rating& r) {
  const bool rated = preset.actuator_data.given ||
                     std::any_of(preset.parameters.begin(), preset.parameters.end(),
                                 [](const auto& p) { return motor_parameter(p.first) != nullptr; });
  if (!rated) return std::nullopt;
  if (!r.lead_m_per_rev) return r.peak_torque_Nm;
  return r.peak_torque_Nm * 2.0 * M_PI / *r.lead_m_per_rev;  // N through the screw or capstan
}

}  // namespace

Preset described_twin(const Preset& preset) {
  if (!preset.description.empty()) return preset;
  const std::string twin = preset.mechanism + "-described";
  const std::vector<std::string> presets = available_presets();
  if (std::find(presets.begin(), presets.end(), twin) == presets.end())
    throw std::invalid_argument(preset.mechanism + " is compiled and has no described twin ('" + twin +
                                "'): only a device with a chain description can be written as MJCF");
  Preset described = load_preset(twin);
  const Preset defaults = load_preset(preset.mechanism);
  for (const auto& [name, value] : preset.parameters) {
    if (described.parameters.count(name) || motor_parameter(name)) described.parameters[name] = value;
    else if (const auto d = defaults.parameters.find(name); d == defaults.parameters.end() || d->second != value)
      throw std::invalid_argument(name + " of " + preset.mechanism + " has no counterpart in " + twin + "; export " +
                                  twin + " with its own parameters");
  }
  described.actuator_data = preset.actuator_data;
  validate(described);
  return described;
}

std::string mjcf_platform_joint(const std::string& coordinate) { return "platform_" + coordinate; }
std::string mjcf_leg_end(const std::string& leg) { return "leg_" + leg + "_end"; }

std::string mjcf_model(const Preset& preset) {
  if (preset.description.empty())
    throw std::invalid_argument("'" + preset.title +
                                "' is compiled, not described: only a described device can be written as MJCF");
  const Kinematics kin(build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit));
  const Model& model = kin.model();
  const PoseSolution home = kin.inverse(model.home, 0, 1e-10);
  if (!assembled(home))
    throw std::invalid_argument("the device does not assemble at home on branch 0 (leg " +
                                model.legs[std::size_t(std::max(home.failing_leg, 0))].name + ")");
  const double metres = haptics::metres_per(model.length_unit);

  std::array<double, 6> coordinates = model.fixed;
  Eigen::VectorXd extras = Eigen::VectorXd::Zero(Eigen::Index(model.extras.size()));
  for (std::size_t k = 0; k < model.task.size(); ++k) {
    const TaskCoordinate& c = model.task[k];
    if (c.platform_coordinate >= 0) coordinates[std::size_t(c.platform_coordinate)] = model.home[Eigen::Index(k)];
    else extras[c.extra] = model.home[Eigen::Index(k)];
  }

  Writer w(metres);
  write_platform(w, model, coordinates, model.platform_frames(extras), metres);
  // The motors as the haptic measures rate them (the preset's, --param ratings, the gear ratio).
  const haptics::DeviceData ratings = haptics::device_data(preset, make_mechanism(preset)->info());
  const std::vector<double> armature = armatures(ratings);
  for (std::size_t l = 0; l < model.legs.size(); ++l)
    write_leg(w, model, model.legs[l], home.legs[l].state, metres, armature);

  const double radius = model.size * metres / 60.0;  // drawing and mass only: links are not modelled as solids yet
  std::ostringstream out;
  out << "<!-- " << escaped(preset.title) << ", written by linkscape export-model: lengths in m, angles in rad;\n"
      << "     joint values are Linkscape's (each hinge's and slide's ref is its value at home, branch 0);\n"
      << "     the legs' ends are welded to the platform, which closes the loops. -->\n"
      << "<mujoco model=\"" << escaped(preset.title) << "\">\n"
      << "  <compiler angle=\"radian\" autolimits=\"true\" boundmass=\"1e-4\" boundinertia=\"1e-9\"/>\n"
      << "  <default>\n"
      << "    <geom density=\"2700\" size=\"" << number(radius) << "\" contype=\"0\" conaffinity=\"0\"/>\n"
      << "    <default class=\"link\"><geom rgba=\"0.55 0.6 0.7 1\"/></default>\n"
      << "    <default class=\"joint\"><geom size=\"" << number(1.5 * radius) << "\" rgba=\"0.9 0.6 0.2 1\"/></default>\n"
      << "    <default class=\"platform\"><geom rgba=\"0.3 0.7 0.4 1\"/></default>\n"
      << "  </default>\n"
      << "  <worldbody>\n"
      << w.text() << "  </worldbody>\n"
      << "  <equality>\n";
  for (const Leg& leg : model.legs) {
    const Eigen::Isometry3d platform_in_end = leg.anchor.inverse();
    const Eigen::Quaterniond q(platform_in_end.rotation());
    out << "    <weld body1=\"" << escaped(mjcf_leg_end(leg.name)) << "\" body2=\""
        << escaped(model.platform_names[std::size_t(leg.platform)]) << "\" relpose=\""
        << w.vector(platform_in_end.translation()) << " " << number(q.w()) << " " << number(q.x()) << " "
        << number(q.y()) << " " << number(q.z()) << "\"/>\n";
  }
  out << "  </equality>\n  <actuator>\n";
  for (std::size_t k = 0; k < model.actuators.size(); ++k) {
    const Actuator& a = model.actuators[k];
    out << "    <motor name=\"" << escaped(a.name) << "\" joint=\"" << escaped(a.name) << "\"";
    if (const auto limit = control_limit(preset, ratings.actuators[k]))
      out << " ctrlrange=\"" << number(-*limit) << " " << number(*limit) << "\"";
    out << "/>\n";
  }
  out << "  </actuator>\n</mujoco>\n";
  return out.str();
}

}  // namespace linkscape::described
