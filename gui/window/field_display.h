// The fields in the view: the slice and the workspace surfaces of the
// device state, sampled as the Field panel says, coarse first, on worker
// threads (a new request supersedes the one in flight), drawn in the
// view's field scene with the colour bar in its own strip. While anything
// moves the picture the surfaces draw light meshes; once nothing does, in full.
#pragma once

#include <QObject>
#include <QString>
#include <memory>

#include "core/field.h"
#include "gui/window/field_job.h"
#include "gui/window/session.h"
#include "render/slice_image.h"

class vtkRenderer;

namespace linkscape::render {
class FieldScene;
}

namespace linkscape::gui {

class DeviceState;
class FieldPanel;
class VtkWidget;

class FieldDisplay : public QObject {
  Q_OBJECT

 public:
  // What is moving the picture every frame.
  enum Moving : unsigned { kSliderDrag = 1, kHandleDrag = 2, kAnimation = 4, kCameraDrag = 8 };

  // `renderer` draws the scene, `legend` the colour bar's strip at its right.
  FieldDisplay(const DeviceState& state, FieldPanel* panel, render::FieldScene* scene, VtkWidget* view,
               vtkRenderer* renderer, vtkRenderer* legend, QObject* parent = nullptr);
  ~FieldDisplay() override;

  // The Field panel's settings for the state's device and pose.
  FieldSettings settings() const;
  // Takes the settings the panel offers; the fields follow.
  void apply(const FieldSettings& settings);
  // Samples the slice and/or the volume again (only what is shown).
  void request(bool slice, bool volume);
  // The slice's colours, contour and range again, without sampling.
  void restyle();
  // What is shown and how opaque, as the panel says.
  void applyVisibility();
  // The scene's and the colour bar's parts of the view.
  void placeLegend();
  void setMoving(Moving source, bool on);
  bool moving() const { return moving_ != 0; }

  // True once the latest request has been answered at full resolution.
  bool settled() const { return slice_settled_ && surfaces_settled_; }
  void markSettled() { slice_settled_ = surfaces_settled_ = true; }
  const Field* slice() const { return slice_field_.get(); }
  const SurfaceResult& surfaces() const { return surfaces_; }
  render::SliceStyle sliceStyle() const;
  FieldJobRunner* sliceRunner() { return &slice_runner_; }
  FieldJobRunner* volumeRunner() { return &volume_runner_; }

 signals:
  void sliceUpdated(bool fine);
  void surfacesUpdated(bool fine);
  void fieldsUpdated(bool fine);
  void changed();                               // a setting of the document changed
  void computed(const QString& text);           // how long the slice and the surfaces took (View > Show timings)
  void message(const QString& text, int msecs);  // for the status bar

 private:
  void onSlice(const SliceResult& result);
  void onSurfaces(const SurfaceResult& result);
  void onFieldChosen();

  const DeviceState& state_;
  FieldPanel* panel_;
  render::FieldScene* scene_;
  VtkWidget* view_;
  vtkRenderer *renderer_, *legend_;
  FieldJobRunner slice_runner_, volume_runner_;
  std::shared_ptr<const Field> slice_field_;
  SurfaceResult surfaces_;  // the last isosurfaces and their volume, for export
  bool slice_settled_ = false, surfaces_settled_ = false;
  unsigned moving_ = 0;       // Moving flags
  bool light_asked_ = false;  // the light meshes of the surfaces shown are made or being made
  QString slice_time_, surfaces_time_;  // the last of each, for computed()
};

}  // namespace linkscape::gui
