#include "gui/window/help_actions.h"

#include <QMessageBox>
#include <vtkVersion.h>
#include <Eigen/Core>

#include "core/simd.h"
#include "core/mechanisms/described/mechanism.h"
#include "render/workspace_mesh.h"

namespace linkscape::gui {

void show_about(QWidget* parent) {
  const QString text =
      QObject::tr("<h3>Linkscape %1</h3>"
                  "<p>Kinematic design of parallel haptic-device mechanisms.</p>"
                  "<p>Built with Qt %2 (running %3), VTK %4, Eigen %5.%6.%7, OpenMesh %8 and Highway %9; "
                  "field kernels on the %10 instruction set.</p>")
          .arg(LINKSCAPE_VERSION, QT_VERSION_STR, qVersion(), vtkVersion::GetVTKVersion())
          .arg(EIGEN_WORLD_VERSION)
          .arg(EIGEN_MAJOR_VERSION)
          .arg(EIGEN_MINOR_VERSION)
          .arg(QString::fromStdString(render::openmesh_version()), QString::fromStdString(simd::highway_version()),
               QString::fromStdString(simd::current_target()));
  QMessageBox::about(parent, QObject::tr("About Linkscape"), text);
}

std::string mechanism_summary(const Preset& preset) {
  if (!preset.description.empty()) return described::describe(preset);
  return preset.title + "\n\ncompiled in C++: core/mechanisms/" + preset.mechanism +
         "/ (closed forms and SIMD field kernels; docs/mechanisms/" + preset.mechanism + ".md)\n";
}

void show_mechanism(QWidget* parent, const Preset& preset) {
  QMessageBox box(parent);
  box.setWindowTitle(QObject::tr("About this mechanism"));
  box.setTextFormat(Qt::PlainText);
  box.setText(QString::fromStdString(preset.title));
  try {
    box.setInformativeText(QString::fromStdString(mechanism_summary(preset)));
  } catch (const std::exception& e) {
    box.setInformativeText(QString::fromStdString(e.what()));
  }
  box.exec();
}

}  // namespace linkscape::gui
