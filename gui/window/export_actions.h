// The window's exports (File menu): the slice, the workspace meshes, the
// volume field, the device as a MuJoCo model, a screenshot and the view
// alone at a chosen size, through
// the headless commands' writers (atomic); the 3-D scene as glTF. Each asks for its file; a
// failure is shown in a message box; without data, nothing happens.
#pragma once

#include <QImage>
#include <functional>
#include <string>

#include "core/field.h"
#include "core/preset.h"
#include "render/slice_image.h"

class QWidget;
class vtkPolyData;
class vtkRenderWindow;

namespace linkscape::gui {

void export_slice_image(QWidget* parent, const Field* slice, const render::SliceStyle& style);
void export_surface_mesh(QWidget* parent, const Field* volume, vtkPolyData* reach, vtkPolyData* well,
                         double cond_threshold);
void export_volume(QWidget* parent, const Field* volume);
void export_screenshot(QWidget* window);
// The design as a MuJoCo model (MJCF; a compiled device through its described
// twin, docs/model-export.md); a device that cannot be written says why.
void export_model(QWidget* parent, const Preset& preset);
// The view's meshes as glTF (render/scene_export.h).
void export_scene(QWidget* parent, vtkRenderWindow* window);
// Asks for a size (suggested: `suggested`, "WIDTHxHEIGHT") and a file, then
// saves draw(width, height) there. Returns the message for the status bar
// (empty when the user cancelled or it failed).
QString export_view_image(QWidget* parent, const QString& suggested, const std::function<QImage(int, int)>& draw);
// An image as PNG, atomically. Throws std::runtime_error if it cannot be written.
void save_png(const QImage& image, const std::string& path);

}  // namespace linkscape::gui
