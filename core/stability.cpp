#include "core/stability.h"

#include <cmath>
#include <stdexcept>

namespace linkscape::stability {

std::string_view to_string(SweepPath path) {
  switch (path) {
    case SweepPath::CosAlpha: return "cos-alpha";
    case SweepPath::BetaGamma: return "beta=gamma";
    case SweepPath::BetaGammaPi: return "beta=gamma+pi";
    case SweepPath::ZAxis: return "z-axis";
    case SweepPath::OuterSphere: return "outer-sphere";
    case SweepPath::InnerSphere: return "inner-sphere";
    case SweepPath::LegStretched: return "leg-stretched";
    case SweepPath::LegFolded: return "leg-folded";
    case SweepPath::LegElbow: return "leg-elbow";
    case SweepPath::Reach: return "reach-boundary";
    case SweepPath::ActuatedSingular: return "J-singular";
  }
  return "unknown";
}

bool is_joint_path(SweepPath path) {
  return path == SweepPath::BetaGamma || path == SweepPath::BetaGammaPi || path == SweepPath::LegStretched ||
         path == SweepPath::LegFolded || path == SweepPath::LegElbow;
}

std::string path_label(const SweepRow& row) {
  return row.path_name.empty() ? std::string(to_string(row.path)) : row.path_name;
}

std::vector<double> sweep_eps(const SweepOptions& o) {
  if (!(o.eps_max > o.eps_min) || !(o.eps_min > 0) || !(o.eps_max < 1) || o.steps_per_decade < 1 ||
      o.base_points < 1)
    throw std::invalid_argument("sweep: expected 0 < eps_min < eps_max < 1, steps_per_decade >= 1, base_points >= 1");
  std::vector<double> eps;
  const int steps = int(std::lround(std::log10(o.eps_max / o.eps_min) * o.steps_per_decade));
  for (int k = 0; k <= steps; ++k) eps.push_back(o.eps_max * std::pow(10.0, -double(k) / o.steps_per_decade));
  return eps;
}

}  // namespace linkscape::stability
