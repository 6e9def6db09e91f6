#include "gui/window/docks.h"

#include <QComboBox>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QLabel>
#include <QMainWindow>
#include <QProgressBar>
#include <QScrollArea>
#include <QScrollBar>
#include <QStatusBar>
#include <memory>

#include "gui/window/field_job.h"
#include "gui/window/methods_panel.h"
#include "gui/window/vtk_widget.h"

namespace linkscape::gui {

QDockWidget* add_dock(QMainWindow* window, const QString& title, const QString& name, QWidget* content) {
  auto* d = new QDockWidget(title, window);
  d->setObjectName(name);
  // A choice as wide as its longest item would widen the panel past the
  // dock (cut off under its tabs): each shows what fits, the list the rest.
  for (QComboBox* box : content->findChildren<QComboBox*>()) {
    box->setSizeAdjustPolicy(QComboBox::AdjustToMinimumContentsLengthWithIcon);
    box->setMinimumContentsLength(6);
  }
  // Scrollable, so a tall panel never makes the window taller than the screen.
  auto* scroll = new QScrollArea(d);
  scroll->setWidget(content);
  scroll->setWidgetResizable(true);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);  // panels fit the dock's width
  scroll->setFrameShape(QFrame::NoFrame);
  // As wide as the panel needs, so nothing is cut off under the dock's tabs.
  scroll->setMinimumWidth(content->minimumSizeHint().width() + scroll->verticalScrollBar()->sizeHint().width());
  d->setWidget(scroll);
  window->addDockWidget(Qt::RightDockWidgetArea, d);
  return d;
}

FieldStatus add_field_status(QMainWindow* window, VtkWidget* view, std::initializer_list<FieldJobRunner*> runners,
                             const std::function<void()>& on_failure) {
  FieldStatus s;
  s.frame = new QLabel(window);
  s.frame->setObjectName("frameLabel");
  s.compute = new QLabel(window);
  s.compute->setObjectName("computeLabel");
  s.progress = new QProgressBar(window);
  s.progress->setRange(0, 100);
  s.progress->setMaximumWidth(160);
  s.progress->setVisible(false);
  window->statusBar()->addPermanentWidget(s.compute);
  window->statusBar()->addPermanentWidget(s.progress);
  window->statusBar()->addPermanentWidget(s.frame);
  // Timings are for whoever tunes the program: shown from View > Show timings.
  s.compute->setVisible(false);
  s.frame->setVisible(false);
  QObject::connect(view, &VtkWidget::rendered, s.frame,
                   [label = s.frame](double ms) { label->setText(QObject::tr("frame %1 ms").arg(ms, 0, 'f', 1)); });
  // The bar shows only work that lasts (a job's first report starts the
  // clock; shown after kShowAfterMs), and moves at most every kStepMs: a
  // progress bar repaints at once, and the window's short jobs (a slice, a
  // volume re-sampled as the device moves) reported up to 200 times each,
  // every report a repaint that held up the frames (docs/performance.md).
  constexpr qint64 kShowAfterMs = 300, kStepMs = 100;
  struct Clock {
    QElapsedTimer since_start, since_step, since_report;
  };
  for (FieldJobRunner* runner : runners) {
    auto clock = std::make_shared<Clock>();
    QObject::connect(runner, &FieldJobRunner::progress, s.progress, [bar = s.progress, clock](double f) {
      if (f >= 1.0) {
        clock->since_start.invalidate();
        bar->setVisible(false);
        return;
      }
      // A superseded job reports no end: after a pause, the clock starts again.
      if (!clock->since_start.isValid() || !clock->since_report.isValid() || clock->since_report.elapsed() > kShowAfterMs)
        clock->since_start.start();
      clock->since_report.start();
      if (clock->since_start.elapsed() < kShowAfterMs) return;
      if (!bar->isHidden() && clock->since_step.isValid() && clock->since_step.elapsed() < kStepMs) return;
      clock->since_step.start();
      bar->setValue(int(f * 100));
      bar->setVisible(true);
    });
    QObject::connect(runner, &FieldJobRunner::failed, window, [window, bar = s.progress, on_failure](const QString& m) {
      window->statusBar()->showMessage(QObject::tr("Field computation failed: %1").arg(m), 8000);
      bar->setVisible(false);
      on_failure();
    });
  }
  return s;
}

MethodsPanel* add_methods_dock(QMainWindow* window, const Preset& preset, QDockWidget* tab_with) {
  auto* panel = new MethodsPanel;
  panel->setMechanism(preset);
  QDockWidget* d = add_dock(window, QObject::tr("Methods"), "methodsDock", panel);
  window->tabifyDockWidget(tab_with, d);
  return panel;
}

}  // namespace linkscape::gui
