// Argument checks the Delta's sources share (delta.cpp, skeleton.cpp); not
// part of its interface.
#pragma once

#include <Eigen/Core>
#include <string>

#include "core/mechanisms/delta/delta.h"

namespace linkscape::delta::checks {

// "(x, y, z)" for messages.
std::string format_vector(const Eigen::Vector3d& v);
// Throws std::invalid_argument, naming `who`, unless the finite (q, p)
// closes the legs to within 1e-6 of the device's size.
void require_closure(const Model& m, const Eigen::Vector3d& q, const Eigen::Vector3d& p, const char* who);

}  // namespace linkscape::delta::checks
