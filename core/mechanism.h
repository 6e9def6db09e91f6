// One interface for every device. A device describes itself (parameters,
// actuators, task coordinates, methods, measures, singular sets, skeleton)
// and does its own kinematics; everything above core (fields, commands,
// sessions, render scenes, the window) works through this interface and
// never asks which device it has.
//
// A Mechanism is immutable once made (pinocchio's Model): one instance is
// shared by every thread, and a design change makes a new instance through
// the registry. Vectors of coordinates are ordered as the description lists
// them; lengths are in the device's length unit, angles in radians.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/field.h"
#include "core/interference.h"
#include "core/method_harness.h"
#include "core/range.h"
#include "core/stability.h"
#include "core/status.h"

namespace linkscape {

struct Preset;

// ---- The description ----------------------------------------------------------

// A named scalar: a design parameter, an actuated or a task coordinate.
struct Quantity {
  std::string name;         // "L1", "q1", "x", "rz", "h0"
  std::string unit;         // "cm", "rad", "deg", "" (dimensionless)
  std::string description;  // one line a tooltip can show
  double value = 0.0;       // current (parameters) or home (coordinates)
  // The span a designer explores (parameter and task sliders) or the travel
  // (actuators). Whether a parameter value is valid is the model's to say.
  Range range;
  bool in_panel = true;  // parameters: shown in the design panel (else preset/--param only)
};

struct NamedItem {
  std::string name;         // as typed on the command line: "planar", "cond_jo"
  std::string title;        // as shown: "c(J)", "cond(Jo)"
  std::string description;  // one line
};

struct MechanismInfo {
  std::string name;         // preset mechanism name, e.g. "delta"; a described device: its preset's name
  std::string title;        // "Delta parallel haptic device"
  std::string length_unit;  // of the model's lengths, from the preset
  std::string size_description;  // what Mechanism::size() measures, e.g. "L1 + L2" (fit's size)
  std::vector<Quantity> parameters;  // design parameters, as the preset names them
  std::vector<Quantity> actuators;   // q, as eval --fk reads them
  // x: the first three are the position x, y, z of the driven point; any
  // further ones (orientation, grip) are held fixed while fields sample x, y, z.
  std::vector<Quantity> task;
  // Set for a planar device: its driven point moves in the plane
  // z = *plane_z of the base frame, so z is not a freedom. Every point-wise
  // call (inverse, forward's seed, jacobian, measures, reach_margin,
  // nearest_singularity, skeleton_pose) throws std::invalid_argument for a
  // task whose z is off that plane; J then has no z row (its rows: x, y, and
  // any further driven coordinates). Fields over a 3-D grid show the plane's
  // field extruded along z. Unset for a spatial device.
  std::optional<double> plane_z;
  std::vector<NamedItem> ik_methods;  // the first is the default
  // The IK methods that start from IkOptions::seed; the others ignore it (a
  // closed form; a described device's legs, solved from seeds of their own).
  std::vector<std::string> seeded_ik_methods;
  std::vector<NamedItem> fk_methods;  // the first is the default
  // Conditioning measures, the first the main one (fields' "cond"); a second
  // one, where defined, fills the fields' second condition array.
  std::vector<NamedItem> measures;
  std::vector<NamedItem> singular_sets;
  // Per-sample arrays the device's fields always carry as Field::extras
  // besides the kinematic ones: a described device's joint_margin (deg) and
  // clearance (length unit) where its description states stops or links.
  std::vector<NamedItem> extra_fields;
  std::vector<std::string> branches;  // assembly branches (IK), at least one
  // Task coordinates that forward kinematics reads rather than computes (a
  // grip measured by its own sensor): eval --fk reads them beside q.
  std::vector<std::string> fk_inputs;
  // The columns of eval's output (a contract the README documents):
  //   --ik: task, [branch], status, [failing part], actuators, measures, [det], [residual, iterations]
  //   --fk: actuators, fk_inputs, [status], other task coordinates, [measures, det], [iterations, residual]
  struct EvalColumns {
    bool ik_branch = true;
    std::string ik_failing_part;  // column name, empty: none
    bool ik_det = true;
    bool ik_diagnostics = true;   // residual, iterations
    bool fk_status = true;
    bool fk_measures = true;      // measures and det
    bool fk_diagnostics = true;   // iterations, residual
  } eval_columns;
};

// ---- Results -------------------------------------------------------------------

// The tightest IK tolerance asked for: double precision closes a chain to
// a few 1e-16 of the device's size, so a tighter one would call closing
// poses unreachable.
inline constexpr double kFinestTolerance = 1e-15;
// The loosest: past a thousandth of the size an "ok" answer is no longer
// the device's pose.
inline constexpr double kCoarsestTolerance = 1e-3;

struct IkOptions {
  std::string method;                    // empty: the first of info().ik_methods
  std::optional<int> branch;             // only this branch
  std::optional<Eigen::VectorXd> seed;   // actuators, for iterative methods
  double tolerance = 1e-10;              // accept when residual <= tolerance * size()
  int max_iterations = 100;
};

struct IkSolution {
  Eigen::VectorXd q;  // actuated coordinates
  int branch = 0;
  Status status = Status::Ok;
  double residual = 0.0;  // |forward(q) - x| in the task, length unit
  int iterations = 0;     // 0 for closed forms
  std::string method;     // the method that produced it
  std::string failing_part;  // a solution that is not Ok: the part at fault, where the device can say
};

struct IkResult {
  Status status = Status::Unreachable;  // Ok if any solution is Ok
  std::vector<IkSolution> solutions;    // at most one per branch, in branch order
  std::string failing_part;             // e.g. "3" (leg 3), where the device can say
  std::string status_text;              // replaces to_string(status) where set (e.g. "invalid-grip")
};

struct FkOptions {
  std::string method;                   // empty: the first of info().fk_methods
  // Task coordinates to start from (iterative methods); the coordinates
  // listed in info().fk_inputs are read from here. Default: home_task().
  std::optional<Eigen::VectorXd> seed;
  double tolerance = 1e-12;
  int max_iterations = 50;
};

struct FkResult {
  Status status = Status::NotConverged;
  std::string status_text;  // replaces to_string(status) where set
  Eigen::VectorXd x;        // task coordinates
  double residual = 0.0;
  int iterations = 0;
};

struct Measures {
  Status status = Status::Ok;   // Singular where J is (numerically) rank deficient
  std::vector<double> values;   // per info().measures; +inf where singular
  double det = 0.0;             // det J where J is square, else 0
};

struct SingularityReport {
  int nearest = 0;                 // index into info().singular_sets
  double distance = 0.0;           // in the task, length unit
  std::vector<double> distances;   // per singular set
};

// ---- The skeleton: what the render scene draws ---------------------------------
//
// Frames and points are named as `p_F_P` (point P from F's origin, in F's
// axes), `R_F_G` (G's axes in F: v_F = R_F_G * v_G, so R_F_H = R_F_G * R_G_H),
// `X_F_G` (the transform F <- G) and `axis_F_A` (a direction, in F). Frame
// names: world (the base), a body's name, or the paper's letter for a leg's
// frames. Lengths in the device's length unit.

enum class JointType { Revolute, Prismatic, Spherical, Universal };

struct Body {
  std::string name;
  // Geometry in the body's own frame: polylines drawn as tubes, and planar
  // polygons drawn as translucent plates.
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  std::vector<std::vector<Eigen::Vector3d>> faces;
  bool ground = false;  // fixed to the base (drawn in the base colour)
};

struct Joint {
  std::string name;
  JointType type = JointType::Revolute;
  int body = 0;                       // the body it is drawn with
  Eigen::Vector3d p_body_joint = Eigen::Vector3d::Zero();        // in the body's frame
  Eigen::Vector3d axis_body_joint = Eigen::Vector3d::UnitZ();    // in the body's frame (unit)
  bool actuated = false;
  std::string label;  // drawn beside the joint where not empty (actuator names, leg numbers)
};

struct SkeletonModel {
  std::vector<Body> bodies;
  std::vector<Joint> joints;
  double scale = 1.0;  // a typical size (tube radii and handles scale with it)
};

enum class BodyState { Normal, Failing };

struct SkeletonPose {
  std::vector<Eigen::Isometry3d> X_world_body;  // per SkeletonModel::bodies
  std::vector<BodyState> states;                 // per body
  Eigen::Vector3d p_world_endpoint = Eigen::Vector3d::Zero();  // the driven point
};

// ---- The interface --------------------------------------------------------------

// A point-wise evaluation the harness and the sweeps time and check.
struct SingularApproach {
  int set = 0;  // index into info().singular_sets
  // Task coordinates near the set, approaching it from a reachable point as
  // eps (0 < eps < 1, relative: a distance eps * size() or an angle eps)
  // shrinks; `k` picks one of several seeded base points.
  std::function<Eigen::VectorXd(double eps, int k)> target;
};

class Mechanism {
 public:
  virtual ~Mechanism() = default;

  virtual const MechanismInfo& info() const = 0;
  // The design as named parameters (preset names, preset units).
  virtual std::map<std::string, double> parameters() const = 0;
  // A typical size of the device (length unit): tolerances are relative to it.
  virtual double size() const = 0;

  // Home: where the window starts and iterative methods seed.
  virtual Eigen::VectorXd home_task() const = 0;
  virtual Eigen::VectorXd home_actuators() const = 0;

  // Every branch, by a named method. Throws std::invalid_argument for an
  // unknown method, a wrong-sized or non-finite x.
  virtual IkResult inverse(const Eigen::VectorXd& x, const IkOptions& options = {}) const = 0;
  // Throws std::invalid_argument for an unknown method, a wrong-sized or non-finite q.
  virtual FkResult forward(const Eigen::VectorXd& q, const FkOptions& options = {}) const = 0;
  // J = dx/dq of the task coordinates it drives (rows; a planar device's
  // omit z) w.r.t. the actuators, at a consistent pair (q, x).
  virtual Eigen::MatrixXd jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& x) const = 0;
  virtual Measures measures(const Eigen::VectorXd& q, const Eigen::VectorXd& x) const = 0;
  // Signed margin of x to the edge of the reachable set (length unit):
  // > 0 inside, 0 on the boundary, < 0 outside.
  virtual double reach_margin(const Eigen::VectorXd& x, int branch = 0) const = 0;
  virtual SingularityReport nearest_singularity(const Eigen::VectorXd& q, const Eigen::VectorXd& x) const = 0;
  virtual std::vector<SingularApproach> singular_approaches() const = 0;
  // Extra read-outs the window lists under the state (label, text), e.g. a
  // second forward-kinematics method beside the first.
  virtual std::vector<std::pair<std::string, std::string>> readouts(const Eigen::VectorXd& q,
                                                                    const Eigen::VectorXd& x) const {
    (void)q, (void)x;
    return {};
  }

  virtual SkeletonModel skeleton_model() const = 0;
  // Throws std::invalid_argument where q, x do not assemble (a drawing would lie).
  virtual SkeletonPose skeleton_pose(const Eigen::VectorXd& q, const Eigen::VectorXd& x,
                                     const IkResult* ik = nullptr) const = 0;

  // The links as capsules at a pose and the pair that sets the clearance
  // (the view draws them); nullopt for a device that states no link radii.
  // Throws std::invalid_argument where q, x do not assemble.
  virtual std::optional<interference::LinkCapsules> link_capsules(const Eigen::VectorXd& q,
                                                                  const Eigen::VectorXd& x) const {
    (void)q, (void)x;
    return std::nullopt;
  }

  // The default sampling box (x, y, z) of fields and meshes, and the slice
  // plane shown first (normal axis, position) for the task pose `x`.
  virtual Eigen::AlignedBox3d default_box() const = 0;
  virtual std::pair<Axis, double> default_slice_plane(const Eigen::VectorXd& x) const = 0;
  // Samples the field over request.grid with the task's other coordinates
  // held at `fixed_task` (its x, y, z are ignored). Devices implement this
  // with their own fast per-block kernel. Returns nullopt when cancelled.
  virtual std::optional<Field> compute_field(const Grid& grid, const Eigen::VectorXd& fixed_task,
                                             const IkOptions& options, int threads,
                                             const FieldProgress& progress) const = 0;
  // Volume of the reachable set where known in closed form (mesh reports it).
  virtual std::optional<double> analytic_reach_volume() const { return std::nullopt; }

  // Speed against accuracy of every method the device has, and sweeps
  // towards each singular set (rows as in core/method_harness.h and
  // core/stability.h). The defaults (core/generic_methods.cpp) time each IK and
  // FK method on targets made by the device's own forward kinematics from
  // random actuator values, and approach each singular set along
  // singular_approaches(); devices with higher-precision references override.
  virtual std::vector<methods::MethodRow> measure_methods(const methods::HarnessOptions& options) const;
  virtual std::vector<stability::SweepRow> stability_sweeps(const stability::SweepOptions& options) const;
};

// ---- The registry ---------------------------------------------------------------

// Makes a device from a preset (its parameters and actuator limits). Throws
// std::invalid_argument naming what is wrong.
using MechanismFactory = std::function<std::shared_ptr<const Mechanism>(const Preset&)>;

// Every device registers under its preset mechanism name; the list is
// fixed at start-up (core/mechanisms/registry.cpp).
std::vector<std::string> registered_mechanisms();
// Throws std::invalid_argument listing the registered names.
std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset);

// The device the program starts with: the registry's first.
std::string default_mechanism();

// A device as a user names it: a registered preset or a description file,
// then "key=value" overrides of its parameters.
struct PresetChoice {
  std::string name_or_path = default_mechanism();
  std::vector<std::string> params;
};
// Loads and overrides; throws std::invalid_argument naming the bad part.
Preset chosen_preset(const PresetChoice& choice);

// A design's parameters: the linkage's (Mechanism::parameters) and the motor
// ratings its preset sets as parameters (core/actuator_data.h), which the
// linkage does not hold. What sessions and design tables record.
std::map<std::string, double> design_parameters(const Mechanism& mechanism, const Preset& preset);

// Convenience: the index of a named item (method, measure), or
// std::invalid_argument listing the names.
int index_of(const std::vector<NamedItem>& items, const std::string& name, const std::string& what);

}  // namespace linkscape
