#include "gui/window/field_job.h"

#include <QMetaObject>
#include <algorithm>
#include <chrono>
#include <vtkPolyData.h>

namespace linkscape::gui {
namespace {

// The same grid at 1/divisor of the resolution (at least 16 samples per axis
// that has more than one).
Grid coarsen(const Grid& g, int divisor) {
  Grid c = g;
  for (int k = 0; k < 3; ++k) {
    if (g.dims[k] == 1) continue;
    c.dims[k] = std::max(16, g.dims[k] / divisor);
    c.spacing(k) = g.spacing(k) * g.dims[k] / c.dims[k];
  }
  return c;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A slice computed from t0 on, with its rate.
SliceResult slice_result(Field&& field, bool fine, std::chrono::steady_clock::time_point t0) {
  SliceResult r{std::make_shared<const Field>(std::move(field)), fine, seconds_since(t0), 0.0};
  r.points_per_second = r.field->grid.size() / std::max(r.seconds, 1e-9);
  return r;
}

}  // namespace

FieldJobRunner::FieldJobRunner(QObject* parent) : QObject(parent) {
  qRegisterMetaType<SliceResult>("linkscape::gui::SliceResult");
  qRegisterMetaType<SurfaceResult>("linkscape::gui::SurfaceResult");
  pool_.setMaxThreadCount(1);  // one job at a time; OpenMP parallelises inside it
}

FieldJobRunner::~FieldJobRunner() {
  cancel();
  pool_.waitForDone();
}

void FieldJobRunner::cancel() {
  if (cancel_) cancel_->store(true);
  ++generation_;
}

bool FieldJobRunner::busy() const { return pool_.activeThreadCount() > 0; }

void FieldJobRunner::submit(const FieldJob& job) {
  cancel();
  if (job.slice && !job.volume && last_slice_seconds_.load() < kAnswerNowWhenFasterThan) {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      std::optional<Field> field = job.sampler(*job.slice, {});
      if (field) {
        const SliceResult sr = slice_result(std::move(*field), true, t0);
        last_slice_seconds_.store(sr.seconds);
        emit sliceReady(sr);
        return;
      }
    } catch (const std::exception& e) {
      emit failed(QString::fromStdString(e.what()));
      return;
    }
  }
  auto cancel_flag = std::make_shared<std::atomic<bool>>(false);
  cancel_ = cancel_flag;
  const std::uint64_t generation = generation_.load();
  pool_.start([this, job, cancel_flag, generation] {
    auto current = [&] { return !cancel_flag->load() && generation_.load() == generation; };
    FieldProgress progress;
    progress.cancel = cancel_flag.get();
    progress.report = [this, &current](double f) {
      if (current()) QMetaObject::invokeMethod(this, [this, f] { emit this->progress(f); }, Qt::QueuedConnection);
    };
    try {
      const bool coarse_slice = last_slice_seconds_.load() >= kCoarseWhenSlowerThan;
      const bool coarse_volume = last_volume_seconds_.load() >= kCoarseWhenSlowerThan;
      for (bool fine : {false, true}) {
        // Slice first: it is what the user is looking at.
        if (job.slice && (fine || coarse_slice)) {
          const Grid grid = fine ? *job.slice : coarsen(*job.slice, job.coarse_divisor);
          const auto t0 = std::chrono::steady_clock::now();
          std::optional<Field> field = job.sampler(grid, progress);
          if (!field || !current()) return;
          const SliceResult sr = slice_result(std::move(*field), fine, t0);
          if (fine) last_slice_seconds_.store(sr.seconds);
          QMetaObject::invokeMethod(this, [this, sr, generation] {
            if (generation_.load() == generation) emit sliceReady(sr);
          }, Qt::QueuedConnection);
        }
        if (!job.volume || (!fine && !coarse_volume)) continue;
        const Grid volume = fine ? *job.volume : coarsen(*job.volume, job.coarse_divisor);
        const auto t1 = std::chrono::steady_clock::now();
        std::optional<Field> vol = job.sampler(volume, progress);
        if (!vol || !current()) return;
        SurfaceResult su;
        su.volume = std::make_shared<const Field>(std::move(*vol));
        render::SurfaceRequest reach_request, cond_request;
        cond_request.surface = render::Surface::WellConditioned;
        cond_request.cond_threshold = job.cond_threshold;
        su.reach = render::extract_surface(*su.volume, reach_request);
        if (!current()) return;
        su.well_conditioned = render::extract_surface(*su.volume, cond_request);
        su.cond_threshold = job.cond_threshold;
        su.fine = fine;
        su.seconds = seconds_since(t1);
        if (fine) last_volume_seconds_.store(su.seconds);
        if (!current()) return;
        QMetaObject::invokeMethod(this, [this, su, generation] {
          if (generation_.load() == generation) emit surfacesReady(su);
        }, Qt::QueuedConnection);
      }
    } catch (const std::exception& e) {
      const QString message = QString::fromStdString(e.what());
      QMetaObject::invokeMethod(this, [this, message] { emit failed(message); }, Qt::QueuedConnection);
    }
  });
}

void FieldJobRunner::submitLight(const SurfaceResult& full) {
  if (!full.fine || !full.volume) return;
  const auto& dims = full.volume->grid.dims;
  if (*std::min_element(dims.begin(), dims.end()) < kLightFromSamples) return;
  const bool reach = full.reach && full.reach->GetNumberOfCells() > 0;
  const bool well = full.well_conditioned && full.well_conditioned->GetNumberOfCells() > 0;
  if (!reach && !well) return;
  const std::uint64_t generation = generation_.load();  // a later submit() supersedes this too
  pool_.start([this, volume = full.volume, threshold = full.cond_threshold, reach, well, generation] {
    auto current = [&] { return generation_.load() == generation; };
    if (!current()) return;  // superseded while it waited behind another job
    try {
      const auto t0 = std::chrono::steady_clock::now();
      SurfaceResult light;
      light.volume = volume;
      light.cond_threshold = threshold;
      light.fine = true;
      render::SurfaceRequest reach_request, cond_request;
      cond_request.surface = render::Surface::WellConditioned;
      cond_request.cond_threshold = threshold;
      if (reach) light.reach_light = render::extract_light_surface(*volume, reach_request);
      if (!current()) return;
      if (well) light.well_conditioned_light = render::extract_light_surface(*volume, cond_request);
      light.seconds = seconds_since(t0);
      if (!current()) return;
      QMetaObject::invokeMethod(this, [this, light, generation] {
        if (generation_.load() == generation) emit lightSurfacesReady(light);
      }, Qt::QueuedConnection);
    } catch (const std::exception&) {
      // Light meshes only save time: the full ones stay drawn.
    }
  });
}

}  // namespace linkscape::gui
