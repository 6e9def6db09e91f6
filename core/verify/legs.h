// Enclosures for certified checks of described devices whose every leg is
// solved in closed form by a certified pattern: crank-rod (the described
// Delta, the 6-RUS hexapod), slide-rod (the linear Delta) and extensible
// (the Gough-Stewart platform). docs/task-volumes.md ("Certified verdicts")
// states what a proof covers.
//
// Each leg closes one distance: its rod (or slide) from the point its
// actuator moves to the centre of its last joint, which the platform
// carries rigidly (orientation and extras held at home). Per leg the closed
// form gives both solutions in +, -, *, /, sqrt; the device's branch rules
// and the actuator's travel select one, as the device selects it; the leg's
// row of M = J^-1 = dq/dx is s^T G / (s . dE/dq), s the rod, G the
// platform's velocity of the joint centre per task rate. The measure is
// c(J) = c(M), or for a device with rotations in its task (hexapods) the
// condition number of J's translational rows, from an enclosure of M^-1.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

#include "core/preset.h"

namespace linkscape::verify {

// The preset with its passive-joint limits and its links' radii removed:
// the device the verdict is about, which confirms counterexamples.
Preset without_stops(const Preset& preset);

class LegsCertifier {
 public:
  // Throws Uncertifiable naming the legs (and their patterns) or the
  // feature that blocks a proof, std::invalid_argument for a branch the
  // device does not have.
  static std::shared_ptr<const LegsCertifier> from_preset(const Preset& preset, int branch);
  ~LegsCertifier();

  // A certified upper bound on the measure over the box, when every point
  // of it assembles in the branch within the travel, away from the device's
  // singular sets, and the bound is below `bound`; nullopt otherwise.
  std::optional<double> condition_bound(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double bound) const;

  // Whether the point certainly fails: out of reach, outside an actuator's
  // travel or closing only on another branch (value +inf), or the measure
  // at least `bound` (value: a certified lower bound on it).
  struct Failure {
    double value = 0;
    std::string reason;
  };
  std::optional<Failure> certain_failure(const Eigen::Vector3d& p, double bound) const;

  // The measure over `bound` in double (+inf where the point does not assemble).
  double badness(const Eigen::Vector3d& p, double bound) const;
  // The measure in long double through the same closed forms (+inf where
  // the point does not assemble in the branch).
  long double reference_measure(const Eigen::Vector3d& p) const;

  // "c(J)", "cond(Jp)": the measure's title as the device names it.
  const std::string& measure_title() const;
  // What the device states that the proof does not cover ("passive-joint
  // limits", "link interference", both joined by "and"); empty: nothing.
  const std::string& not_covered() const;

  struct Model;

 private:
  std::unique_ptr<const Model> model_;
  explicit LegsCertifier(std::unique_ptr<const Model> model);
};

}  // namespace linkscape::verify
