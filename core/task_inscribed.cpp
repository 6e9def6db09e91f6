// The largest sphere and box in a task's good region (core/task.h):
// distance transforms and summed-volume tables over a sampled mask, and the
// coarse-to-fine search for the places that hold them.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/task.h"

namespace linkscape::task {

using Eigen::Vector3d;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

// ---- The largest sphere and box in the good region -------------------------------------

namespace {

// The grid with a ring of failing samples around it, so that shapes stay
// inside the sampled box. A grid one sample thick in z is a section of a
// planar device's plane: ringed in x and y only, its shapes are discs and
// rectangles in it.
struct Padded {
  std::array<int, 3> dims;
  std::array<int, 3> ring;  // samples added before the grid's first, per axis
  std::vector<std::uint8_t> good;
  bool flat() const { return ring[2] == 0; }
  std::size_t index(int i, int j, int k) const { return i + std::size_t(dims[0]) * (j + std::size_t(dims[1]) * k); }
  std::array<int, 3> ijk(std::size_t s) const {
    return {int(s % std::size_t(dims[0])), int((s / std::size_t(dims[0])) % std::size_t(dims[1])),
            int(s / (std::size_t(dims[0]) * dims[1]))};
  }
};

Padded padded(const Grid& g, const std::vector<std::uint8_t>& good) {
  if (good.size() != g.size())
    throw std::invalid_argument("inscribed shape: the mask has " + std::to_string(good.size()) + " samples, the grid " +
                                std::to_string(g.size()));
  const int ring_z = g.dims[2] == 1 ? 0 : 1;
  Padded p{{g.dims[0] + 2, g.dims[1] + 2, g.dims[2] + 2 * ring_z}, {1, 1, ring_z}, {}};
  p.good.assign(std::size_t(p.dims[0]) * p.dims[1] * p.dims[2], 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) p.good[p.index(i + 1, j + 1, k + ring_z)] = good[g.index(i, j, k)];
  return p;
}

// The largest spacing of a grid across the shapes it holds (a plane's
// section: in x and y).
double spacing_of(const Grid& g) { return g.dims[2] == 1 ? g.spacing.head<2>().maxCoeff() : g.spacing.maxCoeff(); }

Vector3d point_of(const Grid& g, const Padded& p, std::size_t s) {
  const auto [i, j, k] = p.ijk(s);
  return g.point(i - p.ring[0], j - p.ring[1], k - p.ring[2]);
}

// One line of the exact squared Euclidean distance transform (Felzenszwalb
// and Huttenlocher, "Distance transforms of sampled functions", 2012):
// f[q] <- min_p h^2 (q - p)^2 + f[p], the lower envelope of parabolas.
void distance_line(std::vector<double>& f, int n, double h, std::vector<int>& v, std::vector<double>& z,
                   std::vector<double>& d) {
  const double h2 = h * h;
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[std::size_t(q)] == kInf) continue;
    double crossing = -kInf;
    while (k >= 0) {
      const int p = v[std::size_t(k)];
      crossing = ((f[std::size_t(q)] + h2 * q * q) - (f[std::size_t(p)] + h2 * p * p)) / (2 * h2 * (q - p));
      if (crossing > z[std::size_t(k)]) break;
      --k;
      crossing = -kInf;
    }
    ++k;
    v[std::size_t(k)] = q;
    z[std::size_t(k)] = crossing;
    z[std::size_t(k) + 1] = kInf;
  }
  for (int q = 0, j = 0; q < n; ++q) {
    if (k < 0) {
      d[std::size_t(q)] = kInf;
      continue;
    }
    while (z[std::size_t(j) + 1] < q) ++j;
    const int p = v[std::size_t(j)];
    d[std::size_t(q)] = h2 * double(q - p) * double(q - p) + f[std::size_t(p)];
  }
  for (int q = 0; q < n; ++q) f[std::size_t(q)] = d[std::size_t(q)];
}

// Per padded sample, the diameter of the largest sphere centred on it that
// holds no failing sample: twice the distance to the nearest one.
std::vector<double> sphere_sizes(const Padded& p, const Vector3d& spacing) {
  std::vector<double> dist(p.good.size());
  for (std::size_t s = 0; s < dist.size(); ++s) dist[s] = p.good[s] ? kInf : 0.0;
  const auto n_max = static_cast<std::size_t>(*std::max_element(p.dims.begin(), p.dims.end()));
  std::vector<double> line(n_max), z(n_max + 1), out(n_max);
  std::vector<int> v(n_max);
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3, n = p.dims[axis];
    for (int jb = 0; jb < p.dims[b]; ++jb)
      for (int ja = 0; ja < p.dims[a]; ++ja) {
        std::array<int, 3> ijk{};
        ijk[a] = ja;
        ijk[b] = jb;
        for (int q = 0; q < n; ++q) {
          ijk[axis] = q;
          line[std::size_t(q)] = dist[p.index(ijk[0], ijk[1], ijk[2])];
        }
        distance_line(line, n, spacing(axis), v, z, out);
        for (int q = 0; q < n; ++q) {
          ijk[axis] = q;
          dist[p.index(ijk[0], ijk[1], ijk[2])] = line[std::size_t(q)];
        }
      }
  }
  for (double& d : dist) d = 2 * std::sqrt(d);
  return dist;
}

// Per padded sample, the largest scale s such that the box s * shape centred
// on it holds no failing sample strictly inside: counts of failing samples
// in any box come from a summed-volume table, the scale by bisection.
std::vector<double> box_sizes(const Padded& p, const Vector3d& spacing, const Vector3d& shape) {
  const int nx = p.dims[0] + 1, ny = p.dims[1] + 1, nz = p.dims[2] + 1;
  std::vector<int> table(std::size_t(nx) * ny * nz, 0);  // failing samples with indices < (i, j, k)
  auto at = [&](int i, int j, int k) -> int& { return table[i + std::size_t(nx) * (j + std::size_t(ny) * k)]; };
  for (int k = 1; k < nz; ++k)
    for (int j = 1; j < ny; ++j)
      for (int i = 1; i < nx; ++i)
        at(i, j, k) = !p.good[p.index(i - 1, j - 1, k - 1)] + at(i - 1, j, k) + at(i, j - 1, k) + at(i, j, k - 1) -
                      at(i - 1, j - 1, k) - at(i - 1, j, k - 1) - at(i, j - 1, k - 1) + at(i - 1, j - 1, k - 1);
  // Failing samples with |offset_k| <= w_k around (i, j, k).
  auto failing_within = [&](const std::array<int, 3>& c, const std::array<int, 3>& w) {
    std::array<int, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(0, c[a] - w[a]);
      hi[a] = std::min(p.dims[a], c[a] + w[a] + 1);
    }
    return at(hi[0], hi[1], hi[2]) - at(lo[0], hi[1], hi[2]) - at(hi[0], lo[1], hi[2]) - at(hi[0], hi[1], lo[2]) +
           at(lo[0], lo[1], hi[2]) + at(lo[0], hi[1], lo[2]) + at(hi[0], lo[1], lo[2]) - at(lo[0], lo[1], lo[2]);
  };
  // The box reaches the failing ring around the grid along the axis where it
  // is longest relative to the grid: there every window stays within the
  // padded grid, whatever the box's aspect ratio. (A plane's section has
  // no ring in z, nor a z extent to its rectangle.)
  const int axes = p.flat() ? 2 : 3;
  double top = kInf;
  for (int a = 0; a < axes; ++a) top = std::min(top, 2 * p.dims[a] * spacing(a) / shape(a));
  // A failing sample at offset d is strictly inside iff |d_k| h_k < s shape_k / 2 for every k.
  auto windows = [&](double scale) {
    std::array<int, 3> w{};
    for (int a = 0; a < axes; ++a) w[a] = int(std::ceil(scale * shape(a) / (2 * spacing(a)))) - 1;
    return w;
  };
  std::vector<double> sizes(p.good.size(), 0.0);
  for (std::size_t s = 0; s < sizes.size(); ++s) {
    if (!p.good[s]) continue;
    const std::array<int, 3> c = p.ijk(s);
    double lo = 0, hi = top;
    for (int it = 0; it < 60 && hi - lo > 1e-10 * top; ++it) {
      const double mid = 0.5 * (lo + hi);
      (failing_within(c, windows(mid)) == 0 ? lo : hi) = mid;
    }
    sizes[s] = lo;
  }
  return sizes;
}

// The best shapes of well-separated places: samples within `slack` of the
// largest size, taken best first, each starting a cluster unless it lies
// within `separation` of a cluster's first sample. At most `count`, and
// with `prefer` also the cluster nearest it.
std::vector<Inscribed> best_places(const Grid& grid, const Padded& p, const std::vector<double>& sizes, double slack,
                                   double separation, std::size_t count, const CentreRegion* region,
                                   const Vector3d* prefer) {
  std::vector<std::uint8_t> allowed = p.good;
  if (region)
    for (std::size_t s = 0; s < allowed.size(); ++s) allowed[s] = allowed[s] && region->contains(point_of(grid, p, s));
  std::vector<std::size_t> order;
  double best = -1;
  for (std::size_t s = 0; s < sizes.size(); ++s)
    if (allowed[s]) best = std::max(best, sizes[s]);
  if (best < 0) return {};
  for (std::size_t s = 0; s < sizes.size(); ++s)
    if (allowed[s] && sizes[s] >= best - slack) order.push_back(s);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
  std::vector<Inscribed> out;
  for (std::size_t s : order) {
    const Vector3d c = point_of(grid, p, s);
    bool near = false;
    for (const Inscribed& o : out) near = near || (o.centre - c).norm() < separation;
    if (near) continue;
    out.push_back({true, sizes[s], c, spacing_of(grid)});
    if (out.size() == count && !prefer) break;
  }
  if (prefer && out.size() > count) {  // the `count` largest, and the nearest of the rest
    const auto nearest = std::min_element(out.begin() + std::ptrdiff_t(count), out.end(),
                                          [&](const Inscribed& a, const Inscribed& b) {
                                            return (a.centre - *prefer).norm() < (b.centre - *prefer).norm();
                                          });
    const Inscribed kept = *nearest;
    out.resize(count);
    out.push_back(kept);
  }
  return out;
}

// Candidate places for the largest shape of `task`'s kind on a sampled mask.
std::vector<Inscribed> candidates(const Grid& grid, const std::vector<std::uint8_t>& good, const TaskVolume& task,
                                  std::size_t count, const CentreRegion* region = nullptr,
                                  const Vector3d* prefer = nullptr) {
  const Padded p = padded(grid, good);
  const double h = spacing_of(grid);
  if (task.shape == Shape::Sphere) {
    const std::vector<double> sizes = sphere_sizes(p, grid.spacing);
    const double best = *std::max_element(sizes.begin(), sizes.end());
    return best_places(grid, p, sizes, 4 * h, std::max(best / 4, 3 * h), count, region, prefer);
  }
  if (!(task.size.array() > 0).all()) throw std::invalid_argument("inscribed box: the shape must have positive edges");
  const std::vector<double> sizes = box_sizes(p, grid.spacing, task.size);
  const double best = *std::max_element(sizes.begin(), sizes.end());
  const double smallest = p.flat() ? task.size.head<2>().minCoeff() : task.size.minCoeff();
  return best_places(grid, p, sizes, 4 * h / smallest, std::max(best * smallest / 4, 3 * h), count, region, prefer);
}

}  // namespace

Inscribed inscribed_sphere(const Grid& grid, const std::vector<std::uint8_t>& good) {
  TaskVolume sphere;
  const auto c = candidates(grid, good, sphere, 1);
  return c.empty() ? Inscribed{false, 0, Vector3d::Zero(), spacing_of(grid)} : c.front();
}

Inscribed inscribed_box(const Grid& grid, const std::vector<std::uint8_t>& good, const Vector3d& shape) {
  TaskVolume box;
  box.shape = Shape::Box;
  box.size = shape;
  const auto c = candidates(grid, good, box, 1);
  return c.empty() ? Inscribed{false, 0, Vector3d::Zero(), spacing_of(grid)} : c.front();
}

std::optional<std::vector<Inscribed>> inscribed_places(const Device& device, const std::vector<Criterion>& criteria,
                                                       const TaskVolume& task, const Eigen::AlignedBox3d& box,
                                                       const InscribedOptions& options, const FieldProgress& progress) {
  if (options.resolution < 4 || options.refinements < 0 || options.refinements > kMaxRefinements || options.places < 1)
    throw std::invalid_argument("inscribed shape: resolution must be at least 4, refinements 0 to " +
                                std::to_string(kMaxRefinements) + ", places at least 1");
  // Samples `region` at the resolution; nullopt if cancelled.
  // A planar device's task is a section of its plane: one layer, on the plane.
  const std::optional<double> plane = device.mechanism->info().plane_z;
  auto sample_region = [&](Eigen::AlignedBox3d region, double done, double share)
      -> std::optional<std::pair<Grid, std::vector<std::uint8_t>>> {
    const double longest = plane ? region.sizes().head<2>().maxCoeff() : region.sizes().maxCoeff();
    if (plane) {
      region.min().z() = *plane - longest / 2;
      region.max().z() = *plane + longest / 2;
    }
    const Vector3d extent = region.sizes();
    std::array<int, 3> dims{};
    for (int k = 0; k < 3; ++k) dims[k] = std::max(4, int(std::lround(options.resolution * extent(k) / longest)));
    if (plane) dims[2] = 1;
    const Grid grid = Grid::box(region.min(), region.max(), dims);
    FieldProgress part = progress;
    if (progress.report) part.report = [&](double f) { progress.report(done + share * f); };
    const std::optional<Field> field = sample(device, criteria, grid, part);
    if (!field) return std::nullopt;
    return std::pair{grid, good_mask(*field, criteria)};
  };
  const double steps = 1.0 + double(options.places + (options.prefer_near ? 1 : 0)) * options.refinements;
  const auto coarse = sample_region(box, 0, 1 / steps);
  if (!coarse) return std::nullopt;
  const CentreRegion* centres = options.centres ? &*options.centres : nullptr;
  const Vector3d* prefer = options.prefer_near ? &*options.prefer_near : nullptr;
  std::vector<Inscribed> places =
      candidates(coarse->first, coarse->second, task, std::size_t(options.places), centres, prefer);
  if (places.empty()) return std::vector<Inscribed>{{false, 0, Vector3d::Zero(), spacing_of(coarse->first)}};
  // Zoom onto each place in turn: a box around the shape found, three cells
  // of the grid that found it wider, sampled at the same resolution.
  std::vector<Inscribed> refined;
  for (std::size_t k = 0; k < places.size(); ++k) {
    Inscribed current = places[k];
    double spacing = spacing_of(coarse->first);
    for (int level = 0; level < options.refinements; ++level) {
      const Vector3d half =
          (task.shape == Shape::Sphere ? Vector3d::Constant(current.size / 2) : Vector3d(current.size * task.size / 2)) +
          Vector3d::Constant(3 * spacing);
      const Eigen::AlignedBox3d region = Eigen::AlignedBox3d(current.centre - half, current.centre + half).intersection(box);
      const auto fine = sample_region(region, (1 + k * options.refinements + level) / steps, 1 / steps);
      if (!fine) return std::nullopt;
      const auto found = candidates(fine->first, fine->second, task, 1, centres);
      if (found.empty()) break;  // the zoom missed what the coarser grid saw: keep that
      current = found.front();
      spacing = spacing_of(fine->first);
    }
    refined.push_back(current);
  }
  std::stable_sort(refined.begin(), refined.end(), [](const Inscribed& a, const Inscribed& b) { return a.size > b.size; });
  return refined;
}

std::optional<Inscribed> largest_inscribed(const Device& device, const std::vector<Criterion>& criteria,
                                           const TaskVolume& task, const Eigen::AlignedBox3d& box,
                                           const InscribedOptions& options, const FieldProgress& progress) {
  const auto places = inscribed_places(device, criteria, task, box, options, progress);
  if (!places) return std::nullopt;
  return places->front();
}

}  // namespace linkscape::task
