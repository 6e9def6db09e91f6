// Field computations for the window, off the GUI thread (on the window's
// Run/Cancel worker, BackgroundTask). A new request cancels the one in
// flight; each request is answered coarse first (fast), then at full
// resolution. Results of superseded requests are dropped.
#pragma once

#include <QObject>
#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <optional>

#include <vtkSmartPointer.h>

#include "core/field.h"
#include "gui/window/background.h"
#include "render/workspace_mesh.h"

class vtkPolyData;

namespace linkscape::gui {

// Samples one mechanism on a grid (its Mechanism::compute_field). Called on a
// worker thread; returns nullopt when cancelled and throws
// std::invalid_argument for a request it refuses.
using FieldSampler = std::function<std::optional<Field>(const Grid&, const FieldProgress&)>;

// A slice, a volume with its isosurfaces, or both. Each is computed twice:
// at resolution / coarse_divisor (at least 16 samples per axis), then in
// full; the coarse pass is left out while the last full one of its kind
// took less than FieldJobRunner::kCoarseWhenSlowerThan (it would only cost
// a frame more before the full picture).
struct FieldJob {
  FieldSampler sampler;
  std::optional<Grid> slice;   // a one-sample-thick grid
  std::optional<Grid> volume;  // sampled for the isosurfaces
  double cond_threshold = 3.0;
  int coarse_divisor = 4;
};

struct SliceResult {
  std::shared_ptr<const Field> field;
  bool fine = false;
  double seconds = 0.0;           // compute time
  double points_per_second = 0.0;
};

struct SurfaceResult {
  vtkSmartPointer<vtkPolyData> reach;
  vtkSmartPointer<vtkPolyData> well_conditioned;
  // The same surfaces from every other sample (render::extract_light_surface),
  // drawn while the device is being moved: set only in lightSurfacesReady.
  vtkSmartPointer<vtkPolyData> reach_light;
  vtkSmartPointer<vtkPolyData> well_conditioned_light;
  std::shared_ptr<const Field> volume;  // the field they came from (for export)
  double cond_threshold = 3.0;          // of the well-conditioned surface
  bool fine = false;
  double seconds = 0.0;
};

class FieldJobRunner : public QObject {
  Q_OBJECT

 public:
  explicit FieldJobRunner(QObject* parent = nullptr);
  ~FieldJobRunner() override;  // cancels and waits

  // Light surfaces are made for volumes of at least this many samples a side.
  static constexpr int kLightFromSamples = 48;
  static constexpr double kCoarseWhenSlowerThan = 0.03;  // seconds: about one software-rendered frame
  // A slice-only job whose last full pass took less than a frame is
  // answered at once, on the calling thread: the frame drawn for the change
  // then shows it, instead of the frame after, which would also share the
  // cores with the volume's pass (seconds).
  static constexpr double kAnswerNowWhenFasterThan = kCoarseWhenSlowerThan;

  // Starts `job`, cancelling any earlier one (it starts once that one has
  // stopped), or answers it at once (above).
  void submit(const FieldJob& job);
  // Makes the light meshes of a full pass's surfaces (from a volume with at
  // least kLightFromSamples samples along each axis, else nothing) and emits
  // lightSurfacesReady; after any running job, superseded by a later submit.
  // Asked for when a drag starts, so that no frame waits on them otherwise.
  void submitLight(const SurfaceResult& full);
  // Stops the job in flight (its results are dropped) and forgets waiting ones.
  void cancel();
  bool busy() const;

 signals:
  void sliceReady(const linkscape::gui::SliceResult& result);
  void surfacesReady(const linkscape::gui::SurfaceResult& result);
  // The light meshes asked for by submitLight, with the full pass's volume.
  void lightSurfacesReady(const linkscape::gui::SurfaceResult& result);
  void progress(double fraction);  // of the current pass
  void failed(const QString& message);

 private:
  void startJob(const FieldJob& job);
  void startLight(const SurfaceResult& full);
  void startWaiting();  // when a run has ended

  // The last full passes' times; a first request (infinity) goes coarse first.
  std::atomic<double> last_slice_seconds_{std::numeric_limits<double>::infinity()};
  std::atomic<double> last_volume_seconds_{std::numeric_limits<double>::infinity()};
  // What starts when the run in flight ends: a job (it cancelled that run),
  // else the light meshes.
  std::optional<FieldJob> waiting_job_;
  std::optional<SurfaceResult> waiting_light_;
  // Last: destroyed (cancelled and joined) before what its work reads.
  BackgroundTask worker_{this, [this] { startWaiting(); }};
};

}  // namespace linkscape::gui
