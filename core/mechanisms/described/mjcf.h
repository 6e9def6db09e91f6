// A described device as a MuJoCo model (MJCF, MuJoCo's XML), for handing a
// design to a simulator (docs/model-export.md).
//
// The tree: the platform hangs from the world by its task coordinates (slides
// x, y, z, then hinges rz, ry, rx, R = Rz Ry Rx; a coordinate the description
// fixes is a fixed frame), each leg is a chain of bodies from the world, one
// per joint; each leg's end is welded to its platform body, which closes the
// loops. Every body is written at the device's home assembly (branch 0), and
// every hinge and slide has `ref` = its value there, so MuJoCo's joint values
// are Linkscape's (a ball joint's quaternion is its rotation relative to the
// home assembly). Lengths in metres, angles in radians, motor torque ranges
// from the preset's actuator data, and the motors' rotor inertia on the
// actuated joints (armature).
#pragma once

#include <string>

#include "core/preset.h"

namespace linkscape::described {

// The MJCF text of a described preset. Throws std::invalid_argument when the
// preset is not a described device or its home does not assemble.
std::string mjcf_model(const Preset& preset);

// The described form of a preset: itself, or for a compiled device its
// described twin, the preset named "<mechanism>-described", with the
// parameters and actuator data they share. Throws std::invalid_argument for
// a compiled device without a twin, or a parameter changed from the
// compiled preset that the twin lacks (refused rather than dropped).
Preset described_twin(const Preset& preset);

// The MJCF names the export gives: the platform's coordinate joints and the
// body a leg ends in (the legs' joints keep the description's names).
std::string mjcf_platform_joint(const std::string& coordinate);  // "platform_x", ...
std::string mjcf_leg_end(const std::string& leg);                // "leg_<name>_end"

}  // namespace linkscape::described
