#include "gui/window/window_parts.h"

#include <QApplication>
#include <QComboBox>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QFileDialog>
#include <QImage>
#include <QMainWindow>
#include <QLabel>
#include <QMessageBox>
#include <QProgressBar>
#include <QScrollArea>
#include <QStatusBar>
#include <QTimer>
#include <chrono>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <iostream>
#include <stdexcept>

#include <QDesktopServices>
#include <QUrl>
#include <vtkVersion.h>
#include <Eigen/Core>

#include "core/atomic_file.h"
#include "core/simd.h"
#include "gui/window/field_job.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/methods_panel.h"
#include "gui/window/session_history.h"
#include "gui/figures/slice_figure.h"
#include "gui/window/vtk_widget.h"
#include "render/field_vtk.h"
#include "render/workspace_mesh.h"

namespace linkscape::gui {

QDockWidget* add_dock(QMainWindow* window, const QString& title, const QString& name, QWidget* content) {
  auto* d = new QDockWidget(title, window);
  d->setObjectName(name);
  // Scrollable, so a tall panel never makes the window taller than the screen.
  auto* scroll = new QScrollArea(d);
  scroll->setWidget(content);
  scroll->setWidgetResizable(true);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);  // panels fit the dock's width
  scroll->setFrameShape(QFrame::NoFrame);
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

void run_off_gui_thread(const std::function<void()>& work) {
  auto job = std::async(std::launch::async, work);
  const auto ready = [&job] { return job.wait_for(std::chrono::seconds(0)) == std::future_status::ready; };
  if (!ready()) {
    QEventLoop loop;
    QTimer poll;
    QObject::connect(&poll, &QTimer::timeout, &loop, [&] {
      if (ready()) loop.quit();
    });
    poll.start(10);
    loop.exec(QEventLoop::ExcludeUserInputEvents);
  }
  job.get();
}

Preset load_checked_preset(const std::string& name_or_path) {
  Preset preset;
  run_off_gui_thread([&] {
    preset = load_preset(name_or_path);
    make_mechanism(preset);
  });
  return preset;
}

MechanismWindow* replace_window(QWidget* window, const Preset& preset, const std::optional<Session>& session,
                                const QString& session_path) {
  auto next = std::make_unique<MechanismWindow>(preset);
  auto* old = qobject_cast<MechanismWindow*>(window);
  if (session) next->applySession(*session);
  else if (old) next->applyFieldSettings(old->fieldSettings());
  next->history()->reset(session ? session_path : QString());
  if (old) {
    next->restoreState(old->saveState());  // the same panels where the user put them
    next->setInteractive(old->interactive());
    old->setInteractive(false);  // it asked already
  }
  next->setAttribute(Qt::WA_DeleteOnClose);
  next->setGeometry(window->geometry());
  MechanismWindow* shown = next.release();
  shown->show();
  if (old) emit old->replacedBy(shown);
  window->close();
  return shown;
}

namespace {

// Unsaved work in `window` may go: asks where the window asks.
bool may_discard(QWidget* window) {
  auto* w = qobject_cast<MechanismWindow*>(window);
  return !w || w->maybeSave();
}

}  // namespace

bool open_session_file(QMainWindow* window, const Preset& current, const QString& path) {
  try {
    const Session s = load_session(path.toStdString());
    const Preset preset = load_checked_preset(s.mechanism);
    auto* w = qobject_cast<MechanismWindow*>(window);
    if (w && preset.mechanism == current.mechanism) {
      w->applySession(s);
      w->history()->reset(path);
    } else {
      replace_window(window, preset, s, path);
    }
  } catch (const std::exception& e) {
    QMessageBox::warning(window, QObject::tr("Cannot open session"), QString::fromStdString(e.what()));
    return false;
  }
  window->statusBar()->showMessage(QObject::tr("Opened %1").arg(path), 4000);
  return true;
}

bool save_session_file(QMainWindow* window, const Session& session, const QString& path) {
  try {
    save_session(session, path.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(window, QObject::tr("Cannot save session"), QString::fromStdString(e.what()));
    return false;
  }
  window->statusBar()->showMessage(QObject::tr("Saved %1").arg(path), 4000);
  return true;
}

QComboBox* make_preset_chooser(QWidget* window, const Preset& current) {
  auto* box = new QComboBox;
  box->setObjectName("presetBox");
  for (const auto& name : available_presets()) box->addItem(QString::fromStdString(name));
  const QString current_name = QString::fromStdString(current.source.stem().string());
  box->setCurrentText(current_name.isEmpty() ? QString::fromStdString(current.mechanism) : current_name);
  box->setToolTip(QString::fromStdString(current.title));
  QObject::connect(box, &QComboBox::activated, window, [window, box, current_name] {
    const QString chosen = box->currentText();
    if (chosen == current_name) return;
    if (!may_discard(window)) {
      const QSignalBlocker block(box);
      box->setCurrentText(current_name);
      return;
    }
    try {
      replace_window(window, load_checked_preset(chosen.toStdString()), std::nullopt);
    } catch (const std::invalid_argument& e) {
      const QSignalBlocker block(box);
      box->setCurrentText(current_name);
      QMessageBox::warning(window, QObject::tr("Cannot open preset"), QString::fromStdString(e.what()));
    }
  });
  return box;
}

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
  try {
    render::write_mesh(well_conditioned ? well : reach, path.toStdString(), *volume, request);
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

namespace detail {

int save_screenshot_when(QWidget& window, const std::string& path, const std::function<bool()>& ready,
                         const std::function<void(std::function<void()>)>& on_update,
                         const std::function<std::string()>& write) {
  int status = 1;
  bool grabbing = false;
  const std::function<void()> grab_when_ready = [&] {
    if (grabbing || !ready()) return;
    grabbing = true;
    // One more frame so the picture shows the last fields.
    QTimer::singleShot(100, &window, [&] {
      try {  // exceptions must not cross Qt's event loop
        const std::string size = write ? write() : [&] {
          const QImage image = VtkWidget::grabWindow(&window);
          save_png(image, path);
          return std::to_string(image.width()) + "x" + std::to_string(image.height());
        }();
        std::cout << "wrote " << path << " (" << size << ")\n";
        status = 0;
      } catch (const std::exception& e) {
        std::cerr << "linkscape: error: " << e.what() << "\n";
      }
      QApplication::quit();
    });
  };
  on_update(grab_when_ready);
  QTimer::singleShot(0, &window, grab_when_ready);
  QTimer::singleShot(60000, &window, [] {
    std::cerr << "linkscape: the window did not finish rendering within 60 s\n";
    QApplication::exit(1);
  });
  QApplication::exec();
  return status;
}

}  // namespace detail

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

void show_documentation(QWidget* parent) {
  // A build's source tree has the docs; an installed copy elsewhere has the manual page.
  const std::filesystem::path docs = LINKSCAPE_SOURCE_DOCS;
  std::error_code ec;
  if (std::filesystem::is_directory(docs, ec) &&
      QDesktopServices::openUrl(QUrl::fromLocalFile(QString::fromStdString(docs.string()))))
    return;
  QMessageBox::information(parent, QObject::tr("Documentation"),
                           QObject::tr("Run 'man linkscape' for every command and option, and "
                                       "'linkscape --help' for a summary."));
}

}  // namespace linkscape::gui
