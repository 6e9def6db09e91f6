// Checks shared by the window tests: frames of the 3-D view, waiting for the
// fields, pixel changes and comparison with committed baseline images.
#pragma once

#include <QDir>
#include <QFile>
#include <QImage>
#include <QtTest>
#include <vtkImageData.h>
#include <vtkImageDifference.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkSmartPointer.h>

#include <cstdlib>
#include <cstring>

#include "gui/window/vtk_widget.h"

namespace window_checks {

// With LINKSCAPE_SCREENSHOTS=<folder>, the window (its views painted in)
// saved there as `name`, to look at.
inline void save_screenshot(QWidget& w, const QString& name) {
  const QByteArray folder = qgetenv("LINKSCAPE_SCREENSHOTS");
  if (!folder.isEmpty())
    linkscape::gui::VtkWidget::grabWindow(&w).save(QDir(QString::fromLocal8Bit(folder)).filePath(name));
}

// Fraction of pixels that differ by more than a small tolerance per channel.
inline double changed_fraction(const QImage& a, const QImage& b) {
  if (a.size() != b.size()) return 1.0;
  int changed = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const QRgb p = a.pixel(x, y), q = b.pixel(x, y);
      if (std::abs(qRed(p) - qRed(q)) + std::abs(qGreen(p) - qGreen(q)) + std::abs(qBlue(p) - qBlue(q)) > 24)
        ++changed;
    }
  return double(changed) / (a.width() * a.height());
}

// The 3-D view's next frame as RGB.
template <class Window>
QImage frame(Window& w) {
  w.view()->requestRender();
  QTest::qWait(60);
  return w.view()->grabFramebuffer().convertToFormat(QImage::Format_RGB888);
}

// Waits until the window's fields are computed in full.
template <class Window>
void wait_settled(Window& w) {
  QTRY_VERIFY_WITH_TIMEOUT(w.fieldsSettled(), 30000);
  QTest::qWait(50);
}

inline vtkSmartPointer<vtkImageData> to_vtk(const QImage& rgb) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(rgb.width(), rgb.height(), 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* dst = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int y = 0; y < rgb.height(); ++y)  // VTK rows go up
    std::memcpy(dst + std::size_t(y) * rgb.width() * 3, rgb.constScanLine(rgb.height() - 1 - y), rgb.width() * 3);
  return image;
}

// Compares with tests/gui/window/baselines/<name>.png using vtkImageDifference (the
// VTK regression-test metric, which tolerates one-pixel shifts). A missing
// baseline is written next to the test binary and the check fails, so that a
// new baseline is looked at before it is committed.
inline void compare_with_baseline(const QImage& image, const QString& name, double threshold) {
  const QString baseline = QString(LINKSCAPE_BASELINES) + "/" + name + ".png";
  const QString produced = QDir::currentPath() + "/" + name + ".png";
  image.save(produced);
  if (!QFile::exists(baseline)) QFAIL(qPrintable("no baseline " + baseline + "; wrote " + produced));
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(baseline.toStdString().c_str());
  reader->Update();
  vtkNew<vtkImageDifference> diff;
  diff->SetInputData(to_vtk(image));
  diff->SetImageConnection(reader->GetOutputPort());
  diff->Update();
  const double error = diff->GetThresholdedError();
  qInfo("%s: thresholded error %.3f (limit %.1f)", qPrintable(name), error, threshold);
  QVERIFY2(error <= threshold, qPrintable(QString("%1 differs from its baseline: error %2 > %3; see %4")
                                              .arg(name).arg(error).arg(threshold).arg(produced)));
}

}  // namespace window_checks

using namespace window_checks;
