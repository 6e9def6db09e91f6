// Task volumes and criteria: what a designer asks of a device. A task is a
// sphere or an axis-aligned box of the driven point's position (the other
// task coordinates held fixed), and criteria are bounds on the measures
// every point of it must meet. docs/task-volumes.md describes the
// evaluation, the inscribed sphere and cube, and their convergence.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/haptics.h"
#include "core/mechanism.h"

namespace linkscape::task {

// ---- Criteria ---------------------------------------------------------------------

// "reach" (the point is reachable in the sampled branch), or a bound on a
// measure: "cond<3" (the device's first measure, also by its name, e.g.
// cond_jp; its other measures by name, e.g. "cond_jo<5"), "force_iso>2" (N), "force_max>5" (N),
// "resolution<0.5" (mm), "inertia<0.2" (kg), or on one of the device's
// extra fields (MechanismInfo::extra_fields, margins bounded from below):
// "joint_margin>5" (deg), "clearance>0.5" (length unit). Every criterion includes reach.
struct Criterion {
  std::string text;      // as given
  std::string measure;   // "reach", "cond", a measure name, a haptic or an extra field's name
  bool above = false;    // the value must exceed the threshold (forces, margins) rather than stay below it
  double threshold = 0;  // in the measure's unit
  // Into info().measures, for a conditioning measure; -1 for an extra field (set by resolve).
  int measure_index = 0;
  bool extra = false;    // one of the device's extra fields (set by resolve)
  bool reach() const { return measure == "reach"; }
  bool haptic() const { return haptics::is_haptic_field(measure); }
};

// The unit of a criterion's values ("" for a ratio such as c(J)): the
// device's length unit for reach and clearance, deg for joint_margin, a
// haptic field's own.
std::string criterion_unit(const Criterion& c, const std::string& length_unit);

// Parses one criterion. Throws std::invalid_argument for a malformed text,
// a threshold no pose can meet (cond below 1, a force or threshold <= 0), or
// a bound on a measure's wrong side (cond>3).
Criterion parse_criterion(const std::string& text);

// For a criterion without < or > (e.g. "cond", left when a shell took an
// unquoted cond>3 as a redirection to a file "3"): advice to quote it,
// "; quote the criterion: 'cond<3' (...)"; else "".
std::string quoting_hint(const std::string& text);

// Criteria as every box and option takes them: separated by commas,
// semicolons or spaces ("cond<3, force_iso>1"; empty parts dropped).
std::vector<std::string> split_criteria(const std::string& text);
// Each of split_criteria's parts parsed (parse_criterion's errors).
std::vector<Criterion> parse_criteria(const std::string& text);
// The criterion with its measure found on the device (its measures, its
// extra fields, and the haptic fields `data` provides). Throws
// std::invalid_argument listing the names it knows, or where the measure
// needs actuator data not given.
Criterion resolve(const Criterion& c, const MechanismInfo& info, const haptics::DeviceData* data);

// ---- Task volumes -----------------------------------------------------------------

// On a planar device (MechanismInfo::plane_z) a task is its section by the
// plane: a sphere is a disc of its diameter, a box the rectangle of its x
// and y edges, centred on the plane (docs/task-volumes.md).
enum class Shape { Sphere, Box };

// A sphere (diameter) or an axis-aligned box (edge lengths) of the driven
// point's position, in the device's length unit, with its centre fixed or
// left free for a search to place.
struct TaskVolume {
  Shape shape = Shape::Sphere;
  Eigen::Vector3d size = Eigen::Vector3d::Constant(1);  // sphere: the diameter thrice; box: x, y, z edges
  std::optional<Eigen::Vector3d> centre;
  std::string text;  // as given
  double diameter() const { return size.x(); }
  // The box around the volume at `centre`.
  Eigen::AlignedBox3d bounds(const Eigen::Vector3d& centre) const;
  bool contains(const Eigen::Vector3d& p, const Eigen::Vector3d& centre) const;
  double volume() const;
};

// "sphere:diameter=15", "sphere:radius=7.5", "box:size=10,8,6", "box:size=10"
// (a cube), each optionally followed by ",centre=x,y,z". Throws
// std::invalid_argument for an unknown shape or key, a missing size, or an
// empty task (a size that is not positive and finite).
TaskVolume parse_task(const std::string& text);
// The text parse_task reads back to the same volume (shortest round-trip
// numbers): "sphere:diameter=15,centre=0,12.5,-3".
std::string to_text(const TaskVolume& task);

// Where a search may place a task's centre: anywhere in an axis-aligned box
// or a ball (a planar device: its section by the plane).
struct CentreRegion {
  Shape shape = Shape::Box;
  Eigen::AlignedBox3d box;                         // Box
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // Sphere
  double radius = 0;                                 // Sphere
  std::string text;                                  // as given
  bool contains(const Eigen::Vector3d& p) const;
  Eigen::AlignedBox3d bounds() const;
};
// "box:min=x,y,z,max=x,y,z" or "sphere:centre=x,y,z,radius=r". Throws
// std::invalid_argument for another shape or key, a missing key, a min
// above a max or a radius that is not positive and finite.
CentreRegion parse_centre_region(const std::string& text);
std::string to_text(const CentreRegion& region);

// ---- What is sampled ----------------------------------------------------------------

// A device with the settings every evaluation shares.
struct Device {
  std::shared_ptr<const Mechanism> mechanism;
  Eigen::VectorXd fixed_task;  // the task coordinates beyond x, y, z (its x, y, z are ignored)
  IkOptions ik;                // method and branch
  std::optional<haptics::DeviceData> data;  // needed by haptic criteria
  haptics::TorqueRating torque = haptics::TorqueRating::Continuous;
  int threads = 0;  // 0: all
};

// Every criterion resolved on the device (see resolve). The
// functions below expect resolved criteria.
std::vector<Criterion> resolve(const Device& device, const std::vector<Criterion>& criteria);

// Values of every criterion's measure at one position (point-wise, through
// the interface): reach is the reach margin; measures are +inf (forces and
// margins 0) where the branch has no solution. An extra field's value is the
// device's field kernel's at that one sample. `meets` is whether all criteria hold.
// On a planar device p's z is taken as the plane's (its section).
struct PointValues {
  bool reachable = false;
  std::vector<double> values;  // per criterion
  bool meets = false;
};
PointValues evaluate_point(const Device& device, const std::vector<Criterion>& criteria, const Eigen::Vector3d& p);

// Whether every criterion holds at each sample of a sampled field (the
// device's kernel plus, where a criterion needs them, the haptic arrays).
std::vector<std::uint8_t> good_mask(const Field& field, const std::vector<Criterion>& criteria);
// The field over `grid` a mask of these criteria needs; nullopt if cancelled.
std::optional<Field> sample(const Device& device, const std::vector<Criterion>& criteria, const Grid& grid,
                            const FieldProgress& progress = {});

// ---- A task at a place --------------------------------------------------------------

struct CriterionReport {
  Criterion criterion;
  // The worst value over the task's samples (reach: the smallest reach
  // margin), where it occurs, and the share of the volume meeting it.
  double worst = 0;
  Eigen::Vector3d worst_point = Eigen::Vector3d::Zero();
  double fraction = 0;
  int failing = 0;  // samples (interior and surface) failing it
  // How far the worst value is inside the bound, in the measure's unit
  // (< 0: the task leaves the good region by that much).
  double margin() const;
};

struct TaskReport {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double fraction = 0;  // of the volume (the interior samples) where every criterion holds
  std::vector<CriterionReport> criteria;
  int samples = 0;           // interior and surface samples evaluated
  int failing = 0;           // of them, failing some criterion
  Eigen::Vector3d failing_centroid = Eigen::Vector3d::Zero();  // where it fails (when failing > 0)
  Eigen::AlignedBox3d failing_bounds;
  int resolution = 0;        // of the evaluation
  // The one verdict every report gives: the task meets its criteria when
  // every sample evaluated (interior and surface) meets every criterion.
  bool meets() const { return samples > 0 && failing == 0; }
};

// "7783 of 7784 samples (99.99 %)": a share as counts and a percentage that
// is 100 only when every sample is counted and 0 only when none is.
std::string samples_text(int counted, int samples);
// The verdict in the words every report uses: "meets every criterion at all
// 7784 samples" or "fails: 7783 of 7784 samples (99.99 %) meet every
// criterion", with the evaluation's resolution.
std::string verdict_text(const TaskReport& report);

// Samples the task at `centre`: cell centres of a grid with `resolution`
// samples across its largest extent, and about resolution^2 points on its
// surface (where the worst values usually are). `fraction` is over the
// interior samples (each stands for an equal volume); `worst`, `failing` and
// where it fails count the surface too. Point-wise through the interface,
// in parallel. A planar device: the section, a grid and the rim in the
// plane, at the centre moved onto it. Throws std::invalid_argument for a resolution
// outside 2..kMaxTaskResolution.
// The largest resolution (about resolution^3 points evaluated one by one).
inline constexpr int kMaxTaskResolution = 256;
// The resolution of every verdict by default: fit's, sweep's and the window's Task and Fit tabs'.
inline constexpr int kTaskResolution = 24;
TaskReport evaluate(const Device& device, const std::vector<Criterion>& criteria, const TaskVolume& task,
                    const Eigen::Vector3d& centre, int resolution = kTaskResolution);
// evaluate's report where the task meets the criteria there; nullopt,
// sooner, where a sample fails (the same samples: the same verdict).
std::optional<TaskReport> evaluate_if_meets(const Device& device, const std::vector<Criterion>& criteria,
                                            const TaskVolume& task, const Eigen::Vector3d& centre,
                                            int resolution = kTaskResolution);

// ---- The largest sphere and box in the good region -------------------------------

struct Inscribed {
  bool found = false;  // some sample meets every criterion
  // Sphere: the diameter; box: the scale s of the task's box (s * size fits).
  double size = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double spacing = 0;  // of the finest grid used, length unit (the result's resolution)
};

// On a sampled mask (outside the grid counts as failing): the largest
// sphere centred on a sample that holds no failing sample (diameter twice
// the distance to the nearest one), and the largest scale s such that the
// box s * shape centred on a sample holds no failing sample strictly inside.
// A smooth boundary passes close beyond some failing sample, so these
// converge to the continuous answer at about the spacing; their convergence
// is in docs/task-volumes.md.
Inscribed inscribed_sphere(const Grid& grid, const std::vector<std::uint8_t>& good);
Inscribed inscribed_box(const Grid& grid, const std::vector<std::uint8_t>& good, const Eigen::Vector3d& shape);

// Zooms beyond a few change nothing: after the first the zoomed box keeps
// its size (the shape and three cells around it).
inline constexpr int kMaxRefinements = 10;

struct InscribedOptions {
  int resolution = 64;   // samples along the longest side of the box
  int refinements = 2;   // zooms onto each place found (docs/task-volumes.md)
  int places = 3;        // well-separated places refined (the region may have several near-best)
  std::optional<CentreRegion> centres;  // set: the centre stays in it; else anywhere in the box searched
  // Set: the place nearest this point (fit: the device's home point) is
  // refined too, beside the `places` largest (inscribed_places).
  std::optional<Eigen::Vector3d> prefer_near;
};
// The largest sphere (task.shape Sphere) or scaled task box (Box) inside the
// good region within `box` (e.g. the device's default box): sampled at
// options.resolution; then, for each of the best `places` well-separated
// places, each refinement samples again a box around the shape found, three
// cells wider, at the same resolution. The best after refinement wins.
// nullopt if cancelled.
// Every place refined as largest_inscribed refines them (the `places`
// largest and, with options.prefer_near, the well-separated place nearest
// it), largest first; one entry with found false where no sample meets every
// criterion. nullopt if cancelled.
std::optional<std::vector<Inscribed>> inscribed_places(const Device& device, const std::vector<Criterion>& criteria,
                                                       const TaskVolume& task, const Eigen::AlignedBox3d& box,
                                                       const InscribedOptions& options = {},
                                                       const FieldProgress& progress = {});
std::optional<Inscribed> largest_inscribed(const Device& device, const std::vector<Criterion>& criteria,
                                           const TaskVolume& task, const Eigen::AlignedBox3d& box,
                                           const InscribedOptions& options = {}, const FieldProgress& progress = {});

}  // namespace linkscape::task
