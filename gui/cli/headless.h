// Headless commands: the same core and render code as the window, no display.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mechanism.h"

namespace linkscape::gui {

struct EvalOptions {
  PresetChoice mechanism;
  std::string ik_file;  // CSV x,y,z ("-" = stdin); exclusive with fk_file
  std::string fk_file;  // CSV alpha,beta,gamma (rad)
  std::string method;  // empty: the device's first IK method
  std::optional<int> branch;
  std::optional<Eigen::VectorXd> seed;  // actuators
  double tolerance = 1e-10;
  int max_iterations = 100;
  std::string output = "-";  // file, or "-" for stdout
  bool quiet = false;        // no summary on stderr
};

// Writes the evaluation as CSV. Throws std::invalid_argument for bad input.
void run_eval(const EvalOptions& options, std::istream& stdin_stream, std::ostream& stdout_stream);

// Options shared by the commands that sample a field.
struct SamplingOptions {
  PresetChoice mechanism;
  std::string method;        // empty: the device's first IK method
  int branch = 0;
  double tolerance = 1e-10;  // accept a sample when residual <= tolerance * the device's size
  // The task pose, every coordinate: all but x, y, z are held fixed over
  // the grid; the position places the default slice plane. Empty: home.
  std::string pose;
  // Torque limit of the haptic fields: "continuous" or "peak" (core/haptics.h).
  std::string torque = "continuous";
  bool quiet = false;  // no progress or summary on stderr
};

struct SliceOptions {
  SamplingOptions sampling;
  std::string plane;             // axis=position, length unit; default: the device's first plane
  std::vector<double> extent;    // u_min,u_max,v_min,v_max; default +-reach
  std::string size = "512x512";  // samples along u x v
  std::string field = "cond";    // cond, reach, residual, iterations, status, method, force_iso, force_max, resolution, inertia
  std::string colour_map = "viridis";  // render::colour_maps()
  std::vector<double> contours{3.0};
  std::vector<double> range;     // colour range min,max
  bool linear = false;           // linear colour scale for cond/residual
  bool figure = false;           // axes, colour bar and title (PNG, SVG, PDF)
  std::string output;            // .png, .csv (.svg, .pdf with --figure)
};
void run_slice(const SliceOptions& options);

struct FieldCommandOptions {
  SamplingOptions sampling;
  std::string resolution = "128";  // N or NXxNYxNZ
  std::vector<double> box;         // x_min,x_max,y_min,y_max,z_min,z_max; default +-reach
  std::vector<std::string> fields; // haptic arrays to add: force_iso, force_max, resolution, inertia
  std::string output;              // .vti or .csv
};
void run_field(const FieldCommandOptions& options);

struct MeshOptions {
  SamplingOptions sampling;
  std::string surface = "reach";   // "reach", "cond<T" or a haptic criterion ("force_iso>2")
  std::string resolution = "128";
  std::vector<double> box;
  double decimate = 0;             // max decimation error, length unit; 0 = off
  std::string output;              // .stl .obj .ply .off .vtp
};
// Writes the mesh and prints its statistics to `out`.
void run_mesh(const MeshOptions& options, std::ostream& out);

struct BenchOptions {
  PresetChoice mechanism;
  bool quick = false;   // smaller grids, fewer repeats (for a smoke test)
  std::string csv;      // also write the figures as CSV (plus <stem>.methods.csv, <stem>.sweeps.csv)
  std::string chart;    // error-against-time chart of every method (.png, .svg, .pdf)
  std::string sweeps;   // error-against-eps chart of the stability sweeps (.png, .svg, .pdf)
  // Methods and sweeps of the chosen device and these presets only (side by
  // side); empty: the chosen device and every registered one.
  std::vector<std::string> compare;
};
// Measures field throughput, slice and volume times, isosurfaces, peak
// memory and accuracy against resolution, then every numerical method's time
// per evaluation and error (core/method_harness.h) and the stability sweeps
// (core/stability.h); prints a report to `out`. Charts need a QGuiApplication.
void run_bench(const BenchOptions& options, std::ostream& out);

}  // namespace linkscape::gui
