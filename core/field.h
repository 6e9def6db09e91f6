// Sampling kinematic fields on slices and volumes: condition number,
// reachability and solver diagnostics at every sample of a regular grid.
//
// Samples sit at cell centres. Arrays are stored x fastest, then y, then z
// (VTK's point order), so render/ can wrap them without reordering.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace linkscape {

enum class Axis { X = 0, Y = 1, Z = 2 };
// Accepts "x", "y", "z". Throws std::invalid_argument.
Axis parse_axis(const std::string& name);

struct Grid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   // min corner of the sampled box
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();  // cell size per axis, length unit
  std::array<int, 3> dims{1, 1, 1};                   // samples per axis

  std::size_t size() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
  std::size_t index(int i, int j, int k) const { return i + std::size_t(dims[0]) * (j + std::size_t(dims[1]) * k); }
  Eigen::Vector3d point(int i, int j, int k) const {
    return origin + Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5).cwiseProduct(spacing);
  }
  // The sample axes of a slice with this normal: X -> (y, z), Y -> (x, z), Z -> (x, y).
  static std::array<Axis, 2> slice_axes(Axis normal);
  // A one-sample-thick slice through `position` along `normal`, covering
  // [u_min, u_max] x [v_min, v_max] of its slice axes with nu x nv samples.
  // Throws std::invalid_argument for empty extents or non-positive counts.
  static Grid slice(Axis normal, double position, double u_min, double u_max, double v_min, double v_max,
                    int nu, int nv);
  // The box [min, max] with dims samples per axis. Throws as above.
  static Grid box(const Eigen::Vector3d& min, const Eigen::Vector3d& max, std::array<int, 3> dims);
};

// How a device's field kernel computes its samples (the environment
// variable LINKSCAPE_FIELD_KERNEL chooses it where a request does not):
enum class FieldKernel {
  Scalar,          // the reference: one sample at a time through the device's IK and Jacobian
  Vector,          // the fast kernel (rows of samples, SIMD vectors where the device has them)
  VectorMirrored,  // the same, using the device's exact symmetries where they hold (the default)
};
// LINKSCAPE_FIELD_KERNEL: scalar, vector or vector-mirrored; unset or empty:
// VectorMirrored. Throws std::invalid_argument naming the variable otherwise.
FieldKernel field_kernel_from_environment();

// The field engine refuses a request whose arrays would need more than this
// (every device's default; the headless commands compare their peak with it).
inline constexpr std::size_t kFieldMemoryLimitBytes = std::size_t(6) << 30;

// The memory the system can give now (MemAvailable of /proc/meminfo), in
// bytes; nullopt where it does not say. Commands compare their estimated
// peak with it before any work.
std::optional<double> available_memory_bytes();

namespace detail {
// Sample blocks. Large ones (256 KiB and up) are kept when freed, up to 1 GiB
// in all, and handed out again for a request of the same size, so a field
// re-sampled on the same grid writes into pages already mapped instead of
// faulting in freshly zeroed ones (docs/performance.md).
void* allocate_samples(std::size_t bytes);
void free_samples(void* p, std::size_t bytes) noexcept;
}  // namespace detail

// Allocator that leaves new elements uninitialised: a field's arrays are
// written in full by the sampling loop, and skipping the zero fill means the
// pages are first touched there, in parallel and cancellably.
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  T* allocate(std::size_t n) { return static_cast<T*>(detail::allocate_samples(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { detail::free_samples(p, n * sizeof(T)); }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0) ::new (static_cast<void*>(p)) U;
    else ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using SampleArray = std::vector<T, UninitialisedAllocator<T>>;

struct Field {
  Grid grid;
  // Per sample, index grid.index(i, j, k):
  SampleArray<float> cond;          // c(J); +inf where singular or unreachable
  SampleArray<float> reach_margin;  // signed distance to the workspace boundary, > 0 inside
  SampleArray<float> residual;      // |forward(q) - p| of the solution, length unit; +inf if none
  SampleArray<std::uint8_t> reachable;  // 1 if the branch's solution exists and is within limits
  SampleArray<std::uint8_t> status;     // linkscape::Status of the branch's solution
  SampleArray<std::uint16_t> iterations;
  // The IK method that produced the sample's solution, as the device's own
  // method code (its IK method index or enum value): the requested method,
  // or under a method that falls back to another, the one that served.
  // kNoMethod where no solution exists (unreachable, singular, not
  // converged). Every device's compute_field fills it; a Field assembled by
  // hand may leave it empty ("not recorded").
  SampleArray<std::uint8_t> method_used;
  static constexpr std::uint8_t kNoMethod = 255;
  // The name of each method code (index: the code), as the device's IK
  // methods are named (eval --method), and "lanes" for the samples a
  // described device's SIMD lanes decided; empty where not recorded.
  std::vector<std::string> method_names;
  // Devices with a second measure only (a six-DOF device's orientation
  // block), else empty: cond holds the first measure and this the second;
  // +inf where singular or unreachable.
  SampleArray<float> cond_orientation;
  // Further per-sample arrays computed over the field by generic code (the
  // haptic measures, core/haptics.h), each named, titled and with its unit.
  struct NamedArray {
    std::string name, title, unit;
    std::string description;  // how it was computed (e.g. the torque rating and the data's source)
    SampleArray<float> values;
  };
  std::vector<NamedArray> extras;
  const NamedArray* extra(const std::string& name) const {
    for (const NamedArray& a : extras)
      if (a.name == name) return &a;
    return nullptr;
  }
  // Adds an array of grid.size() samples (unset) and returns its samples,
  // which stay where they are as further arrays are added.
  float* add_extra(std::string name, std::string title, std::string unit, std::string description);
  // What was computed, for the metadata of exported files.
  std::string mechanism;
  std::string length_unit;
  std::map<std::string, double> parameters;
  std::map<std::string, std::string> parameter_units;  // where the device gives them (a figure's title); else length_unit
  std::string method;
  int branch = 0;
  // Titles of cond and cond_orientation, from the device's description
  // (e.g. "c(J)"; "cond(Jp)", "cond(Jo)"); empty: the array names.
  std::vector<std::string> measure_titles;

  // Bytes of storage per sample, for the memory limit (cond_orientation adds
  // sizeof(float) where present).
  static constexpr std::size_t bytes_per_sample() { return 3 * sizeof(float) + 3 + sizeof(std::uint16_t); }
};

struct FieldProgress {
  // Called from the calling thread's team with the fraction done (0..1);
  // must be thread-safe and cheap.
  std::function<void(double)> report;
  // When set to true, sampling stops within one grid row and
  // compute_field returns std::nullopt.
  const std::atomic<bool>* cancel = nullptr;
};

// One sample of a field, as a device's kernel computes it
// (detail::fill_field in core/field_sampling.h stores it at its index).
struct FieldSample {
  float cond = 0, reach_margin = 0, residual = 0;
  std::uint8_t reachable = 0, status = 0;
  std::uint16_t iterations = 0;
  std::uint8_t method_used = Field::kNoMethod;
  float cond_orientation = 0;  // the second measure, where the device has one
};

}  // namespace linkscape
