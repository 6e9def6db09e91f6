#include "core/field.h"

#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>
#include <stdexcept>

namespace linkscape {

using Eigen::Vector3d;

namespace detail {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
constexpr std::size_t kHugeThreshold = std::size_t(4) << 20;  // smaller blocks use the heap
std::size_t round_up(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
}  // namespace

void* allocate_samples(std::size_t bytes) {
  if (bytes < kHugeThreshold) return ::operator new(bytes);
  void* p = std::aligned_alloc(kHugePage, round_up(bytes));
  if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  ::madvise(p, round_up(bytes), MADV_HUGEPAGE);  // a hint: without THP it is ignored
#endif
  return p;
}

void free_samples(void* p, std::size_t bytes) noexcept {
  if (bytes < kHugeThreshold) ::operator delete(p);
  else std::free(p);
}

}  // namespace detail

Axis parse_axis(const std::string& name) {
  if (name == "x" || name == "X") return Axis::X;
  if (name == "y" || name == "Y") return Axis::Y;
  if (name == "z" || name == "Z") return Axis::Z;
  throw std::invalid_argument("axis must be x, y or z, got '" + name + "'");
}

std::array<Axis, 2> Grid::slice_axes(Axis normal) {
  switch (normal) {
    case Axis::X: return {Axis::Y, Axis::Z};
    case Axis::Y: return {Axis::X, Axis::Z};
    case Axis::Z: return {Axis::X, Axis::Y};
  }
  return {Axis::X, Axis::Y};
}

Grid Grid::slice(Axis normal, double position, double u_min, double u_max, double v_min, double v_max, int nu,
                 int nv) {
  if (!(u_max > u_min) || !(v_max > v_min) || nu < 1 || nv < 1 || !std::isfinite(position))
    throw std::invalid_argument("slice: extents must satisfy min < max and sizes must be >= 1");
  const auto [u, v] = slice_axes(normal);
  Grid g;
  const int n = int(normal), iu = int(u), iv = int(v);
  g.dims[iu] = nu;
  g.dims[iv] = nv;
  g.dims[n] = 1;
  g.spacing(iu) = (u_max - u_min) / nu;
  g.spacing(iv) = (v_max - v_min) / nv;
  g.spacing(n) = std::min(g.spacing(iu), g.spacing(iv));
  g.origin(iu) = u_min;
  g.origin(iv) = v_min;
  g.origin(n) = position - 0.5 * g.spacing(n);
  return g;
}

Grid Grid::box(const Vector3d& min, const Vector3d& max, std::array<int, 3> dims) {
  Grid g;
  for (int k = 0; k < 3; ++k)
    if (!(max(k) > min(k)) || dims[k] < 1) throw std::invalid_argument("box: need min < max and sizes >= 1 on every axis");
  g.origin = min;
  g.dims = dims;
  g.spacing = (max - min).cwiseQuotient(Vector3d(dims[0], dims[1], dims[2]));
  return g;
}

}  // namespace linkscape
