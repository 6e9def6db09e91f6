#include "gui/window/export_actions.h"

#include <QFileDialog>
#include <QImage>
#include <QInputDialog>
#include <QLineEdit>
#include <QMessageBox>
#include <QStringList>
#include <filesystem>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/haptics.h"
#include "core/mechanisms/described/mjcf.h"
#include "core/size_text.h"
#include "gui/figures/slice_figure.h"
#include "gui/window/vtk_widget.h"
#include "render/field_vtk.h"
#include "render/scene_export.h"
#include "render/workspace_mesh.h"

namespace linkscape::gui {

void export_slice_image(QWidget* parent, const Field* slice, const render::SliceStyle& style) {
  if (!slice) return;
  // A figure (axes, colour bar, legend, title; lines as vector paths) unless
  // the user asks for the bare samples; the method field's colours are
  // categories, so it has no colour bar and goes out bare.
  const QString figure_filter = QObject::tr("Figure (*.png *.svg *.pdf)");
  const QString bare_filter = QObject::tr("Samples only, one pixel each (*.png)");
  QString selected = style.field == "method" ? bare_filter : figure_filter;
  const QString path = QFileDialog::getSaveFileName(parent, QObject::tr("Export slice"), "slice.png",
                                                    figure_filter + ";;" + bare_filter, &selected);
  if (path.isEmpty()) return;
  try {
    const bool figure = selected == figure_filter || !path.endsWith(".png");
    if (figure && style.field == "method")
      throw std::invalid_argument("the method field is exported as a PNG of its samples (its colours are categories)");
    if (figure) write_slice_figure(*slice, style, path.toStdString());
    else render::write_slice_png(*slice, style, path.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Export failed"), QString::fromStdString(e.what()));
  }
}

void export_surface_mesh(QWidget* parent, const Field* volume, vtkPolyData* reach, vtkPolyData* well,
                         double cond_threshold) {
  if (!volume) return;
  QString selected;
  const QString path = QFileDialog::getSaveFileName(
      parent, QObject::tr("Export workspace mesh"), "workspace.stl",
      QObject::tr("Reachable workspace (*.stl *.obj *.ply *.off *.vtp);;"
                  "Well-conditioned workspace (*.stl *.obj *.ply *.off *.vtp)"),
      &selected);
  if (path.isEmpty()) return;
  render::SurfaceRequest request;
  const bool well_conditioned = selected.startsWith("Well");
  if (well_conditioned) {
    request.surface = render::Surface::WellConditioned;
    request.cond_threshold = cond_threshold;
  }
  // CAD tools read bare numbers: the unit is the user's choice (the device's by default).
  QString unit = QString::fromStdString(volume->length_unit);
  QStringList units;
  for (const std::string& u : haptics::length_units()) units << QString::fromStdString(u);
  if (units.contains(unit)) {
    units.move(units.indexOf(unit), 0);
    bool ok = false;
    unit = QInputDialog::getItem(parent, QObject::tr("Export workspace mesh"),
                                 QObject::tr("Length unit of the mesh's points (the device's is %1):").arg(unit), units,
                                 0, false, &ok);
    if (!ok) return;
  }
  try {
    render::write_mesh(well_conditioned ? well : reach, path.toStdString(), *volume, request, unit.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Export failed"), QString::fromStdString(e.what()));
  }
}

void export_volume(QWidget* parent, const Field* volume) {
  if (!volume) return;
  const QString path = QFileDialog::getSaveFileName(parent, QObject::tr("Export field"), "field.vti",
                                                    QObject::tr("VTK image data (*.vti)"));
  if (path.isEmpty()) return;
  try {
    render::write_vti(*volume, path.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Export failed"), QString::fromStdString(e.what()));
  }
}

void export_scene(QWidget* parent, vtkRenderWindow* window) {
  const QString path = QFileDialog::getSaveFileName(parent, QObject::tr("Export scene"), "scene.gltf",
                                                    QObject::tr("glTF 2.0 scene (*.gltf)"));
  if (path.isEmpty()) return;
  try {
    render::write_gltf(window, path.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Export failed"), QString::fromStdString(e.what()));
  }
}

void export_model(QWidget* parent, const Preset& preset) {
  // Refused before asking for a file where the device has no chain description.
  Preset described;
  try {
    described = described::described_twin(preset);
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Export model"), QString::fromStdString(e.what()));
    return;
  }
  const QString path = QFileDialog::getSaveFileName(parent, QObject::tr("Export model (MJCF)"), "model.xml",
                                                    QObject::tr("MuJoCo model (*.xml)"));
  if (path.isEmpty()) return;
  try {
    write_text_atomically(path.toStdString(), described::mjcf_model(described));
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Export failed"), QString::fromStdString(e.what()));
  }
}

void save_png(const QImage& image, const std::string& path) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    if (!image.save(QString::fromStdString(tmp.string()), "PNG")) throw std::runtime_error("cannot write PNG '" + path + "'");
  });
}

void export_screenshot(QWidget* window) {
  const QString path =
      QFileDialog::getSaveFileName(window, QObject::tr("Save screenshot"), "linkscape.png", QObject::tr("PNG (*.png)"));
  if (path.isEmpty()) return;
  try {
    save_png(VtkWidget::grabWindow(window), path.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(window, QObject::tr("Screenshot failed"), QString::fromStdString(e.what()));
  }
}

QString export_view_image(QWidget* parent, const QString& suggested, const std::function<QImage(int, int)>& draw) {
  bool ok = false;
  const QString size = QInputDialog::getText(parent, QObject::tr("Save view image"),
                                             QObject::tr("The 3-D view alone, drawn at this size in pixels (WIDTHxHEIGHT):"),
                                             QLineEdit::Normal, suggested, &ok);
  if (!ok) return {};
  const QString path =
      QFileDialog::getSaveFileName(parent, QObject::tr("Save view image"), "view.png", QObject::tr("PNG (*.png)"));
  if (path.isEmpty()) return {};
  try {
    const auto [width, height] = parse_width_height(size.trimmed().toStdString(), "the size", {16, 16, kMaxWindowSide});
    save_png(draw(width, height), path.toStdString());
    return QObject::tr("Saved %1 (%2)").arg(path, size);
  } catch (const std::exception& e) {
    QMessageBox::warning(parent, QObject::tr("Save view image"), QString::fromStdString(e.what()));
    return {};
  }
}

}  // namespace linkscape::gui
