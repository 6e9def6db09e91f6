// Synthetic fields and file helpers for the field-render tests
// (test_field_render*.cpp): a ball of radius 1 at the origin where
// reach_margin = 1 - |p| and cond = 1 + 4|p| (so cond < 3 is the ball of
// radius 0.5), built here without kinematics.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkStringArray.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/field.h"
#include "render/workspace_mesh.h"

namespace linkscape::render::testing {

// A request for one of the two workspace surfaces (the other members at their defaults).
inline render::SurfaceRequest surface_request(render::Surface surface, double cond_threshold = 3.0) {
  render::SurfaceRequest r;
  r.surface = surface;
  r.cond_threshold = cond_threshold;
  return r;
}

// A field of `dims` samples on the box [lo, hi] (cell-centred), filled from
// the distance d of each sample to `centre`: reachable inside radius `radius`.
inline Field ball_field(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::array<int, 3> dims,
                 const Eigen::Vector3d& centre = Eigen::Vector3d::Zero(), double radius = 1.0,
                 std::function<double(double)> margin = {}) {
  Field f;
  f.grid.origin = lo;
  f.grid.dims = dims;
  for (int a = 0; a < 3; ++a) f.grid.spacing[a] = (hi[a] - lo[a]) / dims[a];
  const std::size_t n = f.grid.size();
  for (auto* a : {&f.cond, &f.reach_margin, &f.residual}) a->resize(n);
  for (auto* a : {&f.reachable, &f.status}) a->resize(n);  // no method_used: "not recorded"
  f.iterations.resize(n);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const std::size_t s = f.grid.index(i, j, k);
        const double d = (f.grid.point(i, j, k) - centre).norm();
        const float m = float(margin ? margin(d) : radius - d);
        const bool inside = m > 0;
        f.reach_margin[s] = m;
        f.reachable[s] = inside;
        f.cond[s] = inside ? float(1 + 4 * d) : std::numeric_limits<float>::infinity();
        f.residual[s] = inside ? float(1e-9 * (1 + d)) : std::numeric_limits<float>::infinity();
        f.status[s] = inside ? 0 : 3;
        f.iterations[s] = std::uint16_t(inside ? 3 + int(10 * d) : 50);
      }
  f.mechanism = "test-ball";
  f.length_unit = "mm";
  f.method = "synthetic";
  f.parameters = {{"L1", 15.0}, {"L2", 15.5}};
  f.branch = 1;
  return f;
}

inline Field cube_ball(int n, double half = 1.3) {
  return ball_field(Eigen::Vector3d::Constant(-half), Eigen::Vector3d::Constant(half), {n, n, n});
}

// A fresh folder per test, removed afterwards; `leftovers()` lists any file
// that is not one of the expected outputs (temporaries are hidden ".*.tmp*").
class Folder {
 public:
  Folder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("linkscape_field_render_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~Folder() { std::filesystem::remove_all(path_); }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(path_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  std::filesystem::path path_;
};

inline std::string string_of(vtkFieldData* fd, const char* name) {
  auto* a = vtkStringArray::SafeDownCast(fd->GetAbstractArray(name));
  return a && a->GetNumberOfValues() == 1 ? a->GetValue(0) : "<missing>";
}
inline double number_of(vtkFieldData* fd, const char* name, int component = 0) {
  vtkDataArray* a = fd->GetArray(name);
  return a ? a->GetComponent(component / a->GetNumberOfComponents(), component % a->GetNumberOfComponents())
           : std::nan("");
}

inline std::array<int, 4> pixel(vtkImageData* image, int x, int y) {
  auto* p = static_cast<unsigned char*>(image->GetScalarPointer(x, y, 0));
  return {p[0], p[1], p[2], p[3]};
}

inline const double kBallVolume = 4.0 / 3.0 * std::numbers::pi;

}  // namespace linkscape::render::testing
