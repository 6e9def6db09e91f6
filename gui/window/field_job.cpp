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
}

FieldJobRunner::~FieldJobRunner() { cancel(); }  // worker_ then joins

void FieldJobRunner::cancel() {
  waiting_job_.reset();
  waiting_light_.reset();
  worker_.cancel();
}

bool FieldJobRunner::busy() const { return worker_.running(); }

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
  if (worker_.running()) waiting_job_ = job;  // starts when the cancelled run has stopped
  else startJob(job);
}

void FieldJobRunner::startWaiting() {
  if (waiting_job_) {
    const FieldJob job = std::move(*waiting_job_);
    waiting_job_.reset();
    startJob(job);
  } else if (waiting_light_) {
    const SurfaceResult full = std::move(*waiting_light_);
    waiting_light_.reset();
    startLight(full);
  }
}

void FieldJobRunner::startJob(const FieldJob& job) {
  worker_.start([this, job](const BackgroundTask::Run& run) {
    FieldProgress progress;
    progress.cancel = &run.cancelled;
    progress.report = [this, &run](double f) { run.progress([this, f] { emit this->progress(f); }); };
    try {
      const bool coarse_slice = last_slice_seconds_.load() >= kCoarseWhenSlowerThan;
      const bool coarse_volume = last_volume_seconds_.load() >= kCoarseWhenSlowerThan;
      for (bool fine : {false, true}) {
        // Slice first: it is what the user is looking at.
        if (job.slice && (fine || coarse_slice)) {
          const Grid grid = fine ? *job.slice : coarsen(*job.slice, job.coarse_divisor);
          const auto t0 = std::chrono::steady_clock::now();
          std::optional<Field> field = job.sampler(grid, progress);
          if (!field || run.cancelled) return;
          const SliceResult sr = slice_result(std::move(*field), fine, t0);
          if (fine) last_slice_seconds_.store(sr.seconds);
          run.progress([this, sr] { emit sliceReady(sr); });
        }
        if (!job.volume || (!fine && !coarse_volume)) continue;
        const Grid volume = fine ? *job.volume : coarsen(*job.volume, job.coarse_divisor);
        const auto t1 = std::chrono::steady_clock::now();
        std::optional<Field> vol = job.sampler(volume, progress);
        if (!vol || run.cancelled) return;
        SurfaceResult su;
        su.volume = std::make_shared<const Field>(std::move(*vol));
        render::SurfaceRequest reach_request, cond_request;
        cond_request.surface = render::Surface::WellConditioned;
        cond_request.cond_threshold = job.cond_threshold;
        su.reach = render::extract_surface(*su.volume, reach_request);
        if (run.cancelled) return;
        su.well_conditioned = render::extract_surface(*su.volume, cond_request);
        su.cond_threshold = job.cond_threshold;
        su.fine = fine;
        su.seconds = seconds_since(t1);
        if (fine) last_volume_seconds_.store(su.seconds);
        run.progress([this, su] { emit surfacesReady(su); });
      }
    } catch (const std::exception& e) {
      run.progress([this, message = QString::fromStdString(e.what())] { emit failed(message); });
    }
  });
}

void FieldJobRunner::submitLight(const SurfaceResult& full) {
  if (!full.fine || !full.volume) return;
  const auto& dims = full.volume->grid.dims;
  if (*std::min_element(dims.begin(), dims.end()) < kLightFromSamples) return;
  if (worker_.running()) {
    if (!waiting_job_) waiting_light_ = full;  // after the job in flight (a waiting job would supersede it)
  } else {
    startLight(full);
  }
}

void FieldJobRunner::startLight(const SurfaceResult& full) {
  const bool reach = full.reach && full.reach->GetNumberOfCells() > 0;
  const bool well = full.well_conditioned && full.well_conditioned->GetNumberOfCells() > 0;
  if (!reach && !well) return;
  worker_.start([this, volume = full.volume, threshold = full.cond_threshold, reach, well](const BackgroundTask::Run& run) {
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
      if (run.cancelled) return;
      if (well) light.well_conditioned_light = render::extract_light_surface(*volume, cond_request);
      light.seconds = seconds_since(t0);
      run.progress([this, light] { emit lightSurfacesReady(light); });
    } catch (const std::exception&) {
      // Light meshes only save time: the full ones stay drawn.
    }
  });
}

}  // namespace linkscape::gui
