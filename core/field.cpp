#include "core/field.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <new>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace linkscape {

// add_extra's pointers survive the vector's growth only if it moves, not copies, its arrays.
static_assert(std::is_nothrow_move_constructible_v<Field::NamedArray>);

float* Field::add_extra(std::string name, std::string title, std::string unit, std::string description) {
  extras.push_back({std::move(name), std::move(title), std::move(unit), std::move(description), {}});
  extras.back().values.resize(grid.size());
  return extras.back().values.data();
}

using Eigen::Vector3d;

namespace detail {

namespace {

// Smaller blocks come and go through the heap. A 512 x 512 slice's arrays
// are 256 KiB to 1 MiB each: kept too, they cost no fresh pages either (its
// CPU time 6.6 -> 4.0 ms; docs/performance.md).
constexpr std::size_t kLargeBlock = std::size_t(256) << 10;

// Freed large blocks, kept for the next request of the same size: the window
// re-samples the same grids over and over, and fresh pages cost a fault and
// a zero fill each (on this project's VM, 0.2-0.9 s for a 256^3 field;
// docs/performance.md). At most kMaxBytes are kept; the oldest go first.
class BlockCache {
 public:
  static constexpr std::size_t kMaxBytes = std::size_t(1) << 30;

  void* take(std::size_t bytes) {
    const std::lock_guard lock(mutex_);
    const auto it = std::find_if(blocks_.begin(), blocks_.end(), [&](const Block& b) { return b.bytes == bytes; });
    if (it == blocks_.end()) return nullptr;
    void* p = it->p;
    kept_ -= bytes;
    blocks_.erase(it);
    return p;
  }
  void keep(void* p, std::size_t bytes) noexcept {
    if (bytes > kMaxBytes) return std::free(p);
    const std::lock_guard lock(mutex_);
    while (kept_ + bytes > kMaxBytes) {
      std::free(blocks_.front().p);
      kept_ -= blocks_.front().bytes;
      blocks_.erase(blocks_.begin());
    }
    try {
      blocks_.push_back({p, bytes});
      kept_ += bytes;
    } catch (...) {
      std::free(p);
    }
  }

 private:
  struct Block {
    void* p;
    std::size_t bytes;
  };
  std::mutex mutex_;
  std::vector<Block> blocks_;  // oldest first
  std::size_t kept_ = 0;
};

// Never destroyed: Fields in static storage may be freed after it would be.
BlockCache& block_cache() {
  static BlockCache* cache = new BlockCache;
  return *cache;
}

}  // namespace

void* allocate_samples(std::size_t bytes) {
  if (bytes < kLargeBlock) return ::operator new(bytes);
  if (void* p = block_cache().take(bytes)) return p;
  void* p = std::malloc(bytes);
  if (!p) throw std::bad_alloc();
  return p;
}

void free_samples(void* p, std::size_t bytes) noexcept {
  if (bytes < kLargeBlock) ::operator delete(p);
  else block_cache().keep(p, bytes);
}

}  // namespace detail

FieldKernel field_kernel_from_environment() {
  const char* value = std::getenv("LINKSCAPE_FIELD_KERNEL");
  if (!value || !*value) return FieldKernel::VectorMirrored;
  const std::string name = value;
  if (name == "scalar") return FieldKernel::Scalar;
  if (name == "vector") return FieldKernel::Vector;
  if (name == "vector-mirrored") return FieldKernel::VectorMirrored;
  throw std::invalid_argument("LINKSCAPE_FIELD_KERNEL must be scalar, vector or vector-mirrored, got '" + name + "'");
}

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

std::optional<double> available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  while (meminfo >> key >> kib) {
    if (key == "MemAvailable:") return kib * 1024;
    meminfo.ignore(64, '\n');
  }
  return std::nullopt;
}

}  // namespace linkscape
