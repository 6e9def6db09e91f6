#include "gui/window/latency_probe.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QSlider>
#include <QTimer>
#include <algorithm>
#include <iomanip>
#include <ostream>
#include <string>
#include <vector>

#include "gui/window/mechanism_window.h"
#include "gui/window/vtk_widget.h"

namespace linkscape::gui {
namespace {

// Runs the event loop until `signal` of `sender` fires or `timeout_ms` pass.
// Returns false on timeout.
template <class Sender, class Signal>
bool wait_for(Sender* sender, Signal signal, int timeout_ms = 60000) {
  QEventLoop loop;
  QTimer timer;
  timer.setSingleShot(true);
  QObject::connect(&timer, &QTimer::timeout, &loop, [&] { loop.exit(1); });
  QObject::connect(sender, signal, &loop, [&] { loop.exit(0); });
  timer.start(timeout_ms);
  return loop.exec() == 0;
}

bool wait_settled(MechanismWindow& w) {
  while (!w.fieldsSettled())
    if (!wait_for(&w, &MechanismWindow::fieldsUpdated)) return false;
  return true;
}

struct Stats {
  double median = 0, p90 = 0, max = 0;
};
Stats stats(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return {};
  return {v[v.size() / 2], v[std::min(v.size() - 1, v.size() * 9 / 10)], v.back()};
}

void show_fields(MechanismWindow& w, bool on) {
  for (QCheckBox* c : w.findChildren<QCheckBox*>())
    if (c->objectName() == "showReachBox" || c->objectName() == "showWellBox" || c->text() == "Slice")
      c->setChecked(on);
}

// Milliseconds from moving an actuator slider (the second, or the only one)
// to the end of the frame that shows it.
std::vector<double> slider_to_frame(MechanismWindow& w, int moves) {
  const auto& actuators = w.mechanism().info().actuators;
  auto* slider = w.findChild<QSlider*>(QString::fromStdString(actuators.at(actuators.size() > 1 ? 1 : 0).name) + "Slider");
  std::vector<double> ms;
  // Held down, as a drag holds it (the window draws lighter workspace
  // surfaces while something is being dragged).
  slider->setSliderDown(true);
  for (int i = 0; i < moves; ++i) {
    QElapsedTimer t;
    t.start();
    slider->setValue(slider->value() + (i % 2 ? -15 : 15));  // 1.5 % of the travel
    if (!wait_for(w.view(), &VtkWidget::rendered)) break;
    ms.push_back(double(t.nsecsElapsed()) / 1e6);
  }
  slider->setSliderDown(false);
  return ms;
}

}  // namespace

int run_latency_probe(MechanismWindow& w, std::ostream& out) {
  if (!wait_settled(w)) {
    out << "latency: the window did not settle within 60 s\n";
    return 1;
  }
  const int kMoves = 40, kLengthChanges = 6;
  struct Row {
    std::string what;
    Stats s;
    std::size_t n;
  };
  std::vector<Row> rows;
  auto add = [&](std::string what, const std::vector<double>& ms) { rows.push_back({what, stats(ms), ms.size()}); };

  w.setDrive(MechanismWindow::Drive::Actuators);
  show_fields(w, false);
  wait_settled(w);
  add("actuator slider -> frame (linkage only)", slider_to_frame(w, kMoves));
  show_fields(w, true);
  if (!wait_settled(w)) return 1;
  add("actuator slider -> frame (slice + isosurfaces)", slider_to_frame(w, kMoves));

  // A design parameter: coarse slice on screen, full slice on screen, full
  // isosurfaces on screen. The surfaces' time with and without View > Smooth
  // workspace surfaces, alternating pair by pair in one run, so that what the
  // smoothing costs is a ratio measured side by side.
  std::vector<double> coarse, full, surfaces, unsmoothed;
  std::string parameter;
  for (const auto& q : w.mechanism().info().parameters)
    if (q.in_panel && parameter.empty()) parameter = q.name;
  const double value = w.mechanism().parameters().at(parameter);
  auto* smooth = w.findChild<QAction*>("smoothSurfacesAction");
  const bool smooth_before = smooth && smooth->isChecked();
  for (int i = 0; i < (smooth ? 2 : 1) * kLengthChanges; ++i) {
    const bool smoothed = smooth ? (i / 2) % 2 == 0 : false;
    if (smooth && smooth->isChecked() != smoothed) {
      smooth->setChecked(smoothed);  // redraws the shown surfaces now
      wait_for(w.view(), &VtkWidget::rendered, 5000);
    }
    double coarse_ms = -1, full_ms = -1, surfaces_ms = -1;
    QElapsedTimer t;
    // Stamps the time of the first frame rendered after `flag` was raised.
    bool coarse_pending = false, full_pending = false, surfaces_pending = false;
    auto c1 = QObject::connect(&w, &MechanismWindow::sliceUpdated, &w, [&](bool fine) {
      (fine ? full_pending : coarse_pending) = true;
    });
    auto c2 = QObject::connect(&w, &MechanismWindow::surfacesUpdated, &w, [&](bool fine) {
      if (fine) surfaces_pending = true;
    });
    auto c3 = QObject::connect(w.view(), &VtkWidget::rendered, &w, [&](double) {
      const double now = double(t.nsecsElapsed()) / 1e6;
      if (coarse_pending && coarse_ms < 0) coarse_ms = now;
      if (full_pending && full_ms < 0) full_ms = now;
      if (surfaces_pending && surfaces_ms < 0) surfaces_ms = now;
    });
    t.start();
    w.setParameters({{parameter, value * (i % 2 ? 1.0 : 1.05)}});
    while (!(full_ms >= 0 && surfaces_ms >= 0))
      if (!wait_for(w.view(), &VtkWidget::rendered)) break;
    QObject::disconnect(c1);
    QObject::disconnect(c2);
    QObject::disconnect(c3);
    if (coarse_ms >= 0) coarse.push_back(coarse_ms);
    if (full_ms >= 0) full.push_back(full_ms);
    if (surfaces_ms >= 0) (smoothed || !smooth ? surfaces : unsmoothed).push_back(surfaces_ms);
  }
  if (smooth) smooth->setChecked(smooth_before);
  // A fast device's slice has no coarse pass (gui/window/field_job.h): nothing to list.
  if (!coarse.empty()) add(parameter + " -> coarse slice on screen", coarse);
  add(parameter + " -> full slice on screen", full);
  add(parameter + (smooth ? " -> full isosurfaces on screen, smoothed" : " -> full isosurfaces on screen"), surfaces);
  if (smooth) add(parameter + " -> full isosurfaces on screen, unsmoothed", unsmoothed);

  out << "Linkscape window latency (" << w.width() << "x" << w.height() << " window, milliseconds)\n";
  out << std::left << std::setw(52) << "what" << std::right << std::setw(9) << "median" << std::setw(9) << "p90"
      << std::setw(9) << "max" << std::setw(5) << "n" << "\n";
  out << std::fixed << std::setprecision(1);
  for (const Row& r : rows)
    out << std::left << std::setw(52) << r.what << std::right << std::setw(9) << r.s.median << std::setw(9)
        << r.s.p90 << std::setw(9) << r.s.max << std::setw(5) << r.n << "\n";
  return 0;
}

}  // namespace linkscape::gui
