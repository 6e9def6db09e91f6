#include "gui/window/field_display.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vtkPolyData.h>
#include <vtkRenderer.h>

#include "core/haptics.h"
#include "gui/window/device_state.h"
#include "gui/window/field_panel.h"
#include "gui/window/vtk_widget.h"
#include "render/colour_scale.h"
#include "render/field_scene.h"
#include "render/skeleton_scene.h"

namespace linkscape::gui {

FieldDisplay::FieldDisplay(const DeviceState& state, FieldPanel* panel, render::FieldScene* scene, VtkWidget* view,
                           vtkRenderer* renderer, vtkRenderer* legend, QObject* parent)
    : QObject(parent), state_(state), panel_(panel), scene_(scene), view_(view), renderer_(renderer), legend_(legend) {
  connect(&slice_runner_, &FieldJobRunner::sliceReady, this, &FieldDisplay::onSlice);
  connect(&volume_runner_, &FieldJobRunner::surfacesReady, this, &FieldDisplay::onSurfaces);
  connect(&volume_runner_, &FieldJobRunner::lightSurfacesReady, this, [this](const SurfaceResult& light) {
    if (light.volume != surfaces_.volume) return;  // for surfaces no longer shown
    scene_->set_light_surface(render::Surface::Reach, light.reach_light);
    scene_->set_light_surface(render::Surface::WellConditioned, light.well_conditioned_light);
    if (moving_) view_->requestRender();
  });
  connect(panel_, &FieldPanel::sliceChanged, this, [this] { request(true, false); });
  connect(panel_, &FieldPanel::volumeChanged, this, [this] { request(false, true); });
  connect(panel_, &FieldPanel::fieldsChanged, this, [this] { request(true, true); });
  connect(panel_, &FieldPanel::styleChanged, this, &FieldDisplay::restyle);
  connect(panel_, &FieldPanel::visibilityChanged, this, &FieldDisplay::applyVisibility);
  connect(panel_, &FieldPanel::fieldChosen, this, &FieldDisplay::onFieldChosen);
}

FieldDisplay::~FieldDisplay() {
  slice_runner_.cancel();
  volume_runner_.cancel();
}

FieldSettings FieldDisplay::settings() const { return panel_->settings(state_.mechanism(), state_.task()); }

void FieldDisplay::apply(const FieldSettings& settings) {
  panel_->apply(settings, state_.mechanism());
  applyVisibility();
  restyle();
  request(true, true);
}

// A haptic field needs its own pass over the slice (core/haptics.h): the
// slice is sampled again when the choice moves to or from one.
void FieldDisplay::onFieldChosen() {
  const bool haptic = haptics::is_haptic_field(settings().field);
  if (haptic || (slice_field_ && !slice_field_->extras.empty())) request(true, false);
  else restyle();
}

void FieldDisplay::request(bool slice, bool volume) {
  emit changed();
  const MechanismInfo& info = state_.mechanism().info();
  const FieldSettings f = settings();
  IkOptions options;
  if (!f.method.empty()) options.method = f.method;
  if (info.branches.size() > 1) options.branch = panel_->fieldBranch();
  FieldJob job;
  job.sampler = [m = state_.shared_mechanism(), fixed = state_.task(), options](const Grid& grid, const FieldProgress& progress) {
    return m->compute_field(grid, fixed, options, 0, progress);
  };
  std::optional<haptics::DeviceData> haptic_data;
  if (haptics::is_haptic_field(f.field)) {
    try {
      haptic_data = haptics::device_data(state_.preset(), info);
    } catch (const std::invalid_argument& e) {
      emit message(QString::fromStdString(e.what()), 8000);
    }
  }
  job.cond_threshold = f.threshold;
  const Eigen::AlignedBox3d box = state_.mechanism().default_box();
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  if (slice && f.show_slice) {
    const Axis normal = panel_->normal();
    const int n = int(normal);
    const double position = std::clamp(f.position, lo(n), hi(n));
    panel_->showPosition(position, state_.mechanism());
    const auto [u, v] = Grid::slice_axes(normal);
    const int res = f.slice_resolution;
    FieldJob slice_job = job;
    if (haptic_data)
      slice_job.sampler = [m = state_.shared_mechanism(), fixed = state_.task(), options, data = *haptic_data](const Grid& grid,
                                                                                    const FieldProgress& progress) {
        return haptics::sample_field(*m, grid, fixed, options, 0, progress, &data);
      };
    slice_job.slice = Grid::slice(normal, position, lo(int(u)), hi(int(u)), lo(int(v)), hi(int(v)), res, res);
    slice_settled_ = false;
    slice_runner_.submit(slice_job);
  } else if (slice) {
    slice_runner_.cancel();
    slice_settled_ = true;
  }
  if (volume && (f.show_reach || f.show_well_conditioned)) {
    const int n = f.volume_resolution;
    FieldJob volume_job = job;
    volume_job.volume = Grid::box(lo, hi, {n, n, n});
    volume_job.coarse_divisor = 2;
    surfaces_settled_ = false;
    volume_runner_.submit(volume_job);
  } else if (volume) {
    volume_runner_.cancel();
    surfaces_settled_ = true;
  }
}

void FieldDisplay::onSlice(const SliceResult& result) {
  slice_field_ = result.field;
  restyle();
  slice_time_ = tr("slice %1 ms, %2 M points/s")
                    .arg(result.seconds * 1e3, 0, 'f', 1)
                    .arg(result.points_per_second / 1e6, 0, 'f', 2);
  emit computed(surfaces_time_.isEmpty() ? slice_time_ : slice_time_ + "; " + surfaces_time_);
  if (result.fine) slice_settled_ = true;
  emit sliceUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

void FieldDisplay::onSurfaces(const SurfaceResult& result) {
  surfaces_ = result;  // kept for export
  scene_->set_surface(render::Surface::Reach, result.reach);
  scene_->set_surface(render::Surface::WellConditioned, result.well_conditioned);
  light_asked_ = false;
  if (moving_ && result.fine) {  // fields that follow the pose: light meshes for the next frames
    light_asked_ = true;
    volume_runner_.submitLight(result);
  }
  applyVisibility();
  // A developer's number: with the slice's, behind View > Show timings.
  surfaces_time_ = tr("isosurfaces (%1) %2 ms").arg(result.fine ? tr("full") : tr("coarse")).arg(result.seconds * 1e3, 0, 'f', 0);
  emit computed(slice_time_.isEmpty() ? surfaces_time_ : slice_time_ + "; " + surfaces_time_);
  if (result.fine) surfaces_settled_ = true;
  emit surfacesUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

render::SliceStyle FieldDisplay::sliceStyle() const {
  const FieldSettings f = settings();
  render::SliceStyle style;
  style.field = f.field;
  style.contour_levels = {f.threshold};
  style.min = f.range_min;
  style.max = f.range_max;
  style.colour_map = f.colour_map;
  style.log_scale = f.log_scale;
  return style;
}

void FieldDisplay::restyle() {
  emit changed();
  const FieldSettings f = settings();
  const bool automatic = !(f.range_min && f.range_max);
  // The range boxes show the range in use: typed, or the automatic one.
  panel_->enableColourRange(!automatic);
  if (!slice_field_) return;
  render::SliceStyle style = render::categorical_style(sliceStyle());  // each status its own colour
  bool clipped_low = false, clipped_high = false;
  if (automatic && !render::is_categorical(style.field)) {
    try {
      // Percentiles, so one spike does not wash out the rest; the bar marks what it clips.
      const render::AutoRange range = render::robust_range(*slice_field_, style);
      style.min = range.lo;
      style.max = range.hi;
      clipped_low = range.clipped_low;
      clipped_high = range.clipped_high;
      panel_->showColourRange(range.lo, range.hi);
    } catch (const std::invalid_argument&) {
      // shown below, where set_slice refuses the same style
    }
  }
  scene_->set_clipped_ends(clipped_low, clipped_high);
  style.scale = std::max(1, 768 / f.slice_resolution);
  style.unreachable_alpha = 50;
  // Below the linkage's rods and knuckles, not through them.
  scene_->set_slice_offset(
      panel_->sliceInPlane() ? -1.2 * render::knuckle_reach(state_.mechanism().skeleton_model().scale) : 0.0);
  try {
    scene_->set_slice(*slice_field_, style);
  } catch (const std::invalid_argument& e) {
    emit message(QString::fromStdString(e.what()), 8000);
  }
  applyVisibility();
}

void FieldDisplay::applyVisibility() {
  emit changed();
  const FieldSettings f = settings();
  const bool slice = f.show_slice && slice_field_ != nullptr;
  scene_->set_slice_visible(slice);
  scene_->set_slice_opacity(panel_->sliceOpacity());
  scene_->set_colour_bar_visible(slice);  // categorical fields get a legend of names
  placeLegend();
  scene_->set_surface_visible(render::Surface::Reach, f.show_reach);
  scene_->set_surface_visible(render::Surface::WellConditioned, f.show_well_conditioned);
  scene_->set_surface_opacity(render::Surface::Reach, f.reach_opacity);
  scene_->set_surface_opacity(render::Surface::WellConditioned, f.well_conditioned_opacity);
  view_->requestRender();
}

void FieldDisplay::setMoving(Moving source, bool on) {
  const unsigned before = moving_;
  moving_ = on ? moving_ | source : moving_ & ~unsigned(source);
  if (bool(before) == bool(moving_)) return;
  scene_->set_light(moving_ != 0);
  if (moving_ && !light_asked_) {
    light_asked_ = true;  // for the surfaces shown; made once, on a worker thread
    volume_runner_.submitLight(surfaces_);
  }
  if (!moving_) view_->requestRender();  // the surfaces in full as soon as nothing moves
}

void FieldDisplay::placeLegend() {
  // About 120 pixels wide, at most a quarter of the view, kept with or
  // without a colour bar: the scene's framing does not move when the bar
  // comes and goes (and the camera fitted to the view does not depend on it).
  const double scale = view_->textScale();  // larger while the view is drawn as a large picture
  const double width = std::min(0.25, 120.0 * scale / std::max(1, view_->width()));
  scene_->set_pixel_scale(scale);
  renderer_->SetViewport(0, 0, 1 - width, 1);
  legend_->SetViewport(1 - width, 0, 1, 1);
}

}  // namespace linkscape::gui
