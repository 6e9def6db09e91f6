// Headless commands: the same core and render code as the window, no display.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace linkscape::gui {

struct MechanismChoice {
  std::string mechanism = "parallel-12r";  // preset name or path
  std::vector<std::string> params;         // "key=value" overrides
};

struct EvalOptions {
  MechanismChoice mechanism;
  std::string ik_file;  // CSV x,y,z ("-" = stdin); exclusive with fk_file
  std::string fk_file;  // CSV alpha,beta,gamma (rad)
  std::string method = "planar";
  std::optional<int> branch;
  std::optional<Eigen::Vector3d> seed;
  double tolerance = 1e-10;
  int max_iterations = 100;
  std::string output = "-";  // file, or "-" for stdout
};

// Writes the evaluation as CSV. Throws std::invalid_argument for bad input.
void run_eval(const EvalOptions& options, std::istream& stdin_stream, std::ostream& stdout_stream);

}  // namespace linkscape::gui
