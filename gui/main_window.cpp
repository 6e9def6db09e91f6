#include "gui/main_window.h"

#include <QApplication>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QImage>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QTimer>
#include <QVBoxLayout>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkRenderer.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>

#include "core/atomic_file.h"
#include "gui/vtk_widget.h"
#include "render/linkage_scene.h"

namespace linkscape::gui {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kSliderStepsPerDegree = 10;

// A pose that shows every link clearly: well conditioned, branch 0.
const Eigen::Vector3d kInitialPose(20 * kDeg, 65 * kDeg, 5 * kDeg);

QString number(double v, int precision = 4) { return QString::number(v, 'g', precision); }

}  // namespace

MainWindow::MainWindow(const Preset& preset, QWidget* parent)
    : QMainWindow(parent), preset_(preset), scene_(std::make_unique<render::LinkageScene>()), q_(kInitialPose) {
  setWindowTitle(QString("Linkscape — %1").arg(QString::fromStdString(preset.title)));
  view_ = new VtkWidget(this);
  setCentralWidget(view_);

  vtkNew<vtkRenderer> renderer;
  renderer->GradientBackgroundOn();
  renderer->SetBackground(0.97, 0.97, 0.98);
  renderer->SetBackground2(0.80, 0.84, 0.90);
  view_->renderWindow()->AddRenderer(renderer);
  renderer_ = renderer;

  scene_->set_model(make_parallel12r(preset_));
  scene_->set_pose(q_);
  scene_->add_to(renderer_);
  scene_->reset_camera(renderer_);

  auto* dock = new QDockWidget(tr("Mechanism and actuators"), this);
  dock->setObjectName("controlsDock");
  auto* panel = new QWidget(dock);
  auto* layout = new QVBoxLayout(panel);
  layout->addWidget(buildMechanismPanel());
  layout->addWidget(buildActuatorPanel());
  layout->addStretch(1);
  dock->setWidget(panel);
  addDockWidget(Qt::RightDockWidgetArea, dock);

  connect(view_, &VtkWidget::rendered, this, [this](double ms) {
    statusBar()->showMessage(tr("frame %1 ms").arg(ms, 0, 'f', 1));
  });
  setPose(q_);
}

MainWindow::~MainWindow() = default;

const parallel12r::Model& MainWindow::model() const { return scene_->model(); }

QWidget* MainWindow::buildMechanismPanel() {
  const auto& m = scene_->model();
  const QString unit = QString::fromStdString(m.length_unit);
  auto* box = new QGroupBox(tr("Mechanism: %1").arg(QString::fromStdString(preset_.mechanism)));
  auto* form = new QFormLayout(box);
  const char* names[] = {"L1", "L2"};
  const double values[] = {m.L1, m.L2};
  for (int i = 0; i < 2; ++i) {
    auto* spin = new QDoubleSpinBox(box);
    spin->setObjectName(QString("%1Box").arg(names[i]));
    spin->setRange(0.01 * values[i], 10.0 * values[i]);
    spin->setDecimals(2);
    spin->setSingleStep(0.05 * values[i]);
    spin->setValue(values[i]);
    spin->setSuffix(" " + unit);
    spin->setToolTip(i == 0 ? tr("Link along u(alpha, beta) (Eqs. 11-13)") : tr("Link along u(alpha, gamma)"));
    form->addRow(names[i], spin);
    length_boxes_[i] = spin;
    connect(spin, &QDoubleSpinBox::valueChanged, this,
            [this] { setLinkLengths(length_boxes_[0]->value(), length_boxes_[1]->value()); });
  }
  return box;
}

QWidget* MainWindow::buildActuatorPanel() {
  auto* box = new QGroupBox(tr("Actuators"));
  auto* form = new QFormLayout(box);
  const auto& m = scene_->model();
  const parallel12r::Interval limits[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
  const char* names[] = {"alpha", "beta", "gamma"};
  const QString symbols[] = {QString::fromUtf8("α (A)"), QString::fromUtf8("β (B)"), QString::fromUtf8("γ (C)")};
  for (int i = 0; i < 3; ++i) {
    // alpha stays inside the open interval (-90, 90) deg of Eq. 14.
    const double lo = std::max(limits[i].lo / kDeg, i == 0 ? -89.9 : -180.0);
    const double hi = std::min(limits[i].hi / kDeg, i == 0 ? 89.9 : 180.0);
    auto* slider = new QSlider(Qt::Horizontal, box);
    slider->setObjectName(QString("%1Slider").arg(names[i]));
    slider->setRange(int(std::lround(lo * kSliderStepsPerDegree)), int(std::lround(hi * kSliderStepsPerDegree)));
    auto* spin = new QDoubleSpinBox(box);
    spin->setObjectName(QString("%1Box").arg(names[i]));
    spin->setRange(lo, hi);
    spin->setDecimals(1);
    spin->setSuffix(QString::fromUtf8(" °"));
    auto* row = new QHBoxLayout;
    row->addWidget(slider, 1);
    row->addWidget(spin);
    form->addRow(symbols[i], row);
    sliders_[i] = slider;
    angle_boxes_[i] = spin;
    connect(slider, &QSlider::valueChanged, this, [this, i](int v) {
      Eigen::Vector3d q = q_;
      q(i) = v * kDeg / kSliderStepsPerDegree;
      setPose(q);
    });
    connect(spin, &QDoubleSpinBox::valueChanged, this, [this, i](double deg) {
      Eigen::Vector3d q = q_;
      q(i) = deg * kDeg;
      setPose(q);
    });
  }
  endpoint_label_ = new QLabel(box);
  endpoint_label_->setObjectName("endpointLabel");
  cond_label_ = new QLabel(box);
  cond_label_->setObjectName("condLabel");
  det_label_ = new QLabel(box);
  singular_label_ = new QLabel(box);
  singular_label_->setObjectName("singularLabel");
  branch_label_ = new QLabel(box);
  for (QLabel* l : {endpoint_label_, cond_label_, det_label_, singular_label_, branch_label_})
    l->setTextInteractionFlags(Qt::TextSelectableByMouse);
  form->addRow(tr("Endpoint D"), endpoint_label_);
  form->addRow(tr("c(J)"), cond_label_);
  form->addRow(tr("det J"), det_label_);
  form->addRow(tr("Nearest singular"), singular_label_);
  form->addRow(tr("Branch"), branch_label_);
  return box;
}

void MainWindow::setPose(const Eigen::Vector3d& q) {
  if (!q.allFinite()) return;
  q_ = q;
  for (int i = 0; i < 3; ++i) {
    const QSignalBlocker block_slider(sliders_[i]), block_box(angle_boxes_[i]);
    sliders_[i]->setValue(int(std::lround(q(i) / kDeg * kSliderStepsPerDegree)));
    angle_boxes_[i]->setValue(q(i) / kDeg);
  }
  scene_->set_pose(q_);
  updateReadouts();
  view_->update();
  emit poseChanged();
}

void MainWindow::setLinkLengths(double L1, double L2) {
  parallel12r::Model m = scene_->model();
  m.L1 = L1;
  m.L2 = L2;
  try {
    scene_->set_model(m);
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(QString::fromStdString(e.what()));
    return;
  }
  updateReadouts();
  view_->update();
}

void MainWindow::updateReadouts() {
  const auto& m = scene_->model();
  const QString unit = QString::fromStdString(m.length_unit);
  const Eigen::Vector3d p = parallel12r::forward(m, q_);
  const auto c = parallel12r::conditioning(m, q_);
  const auto s = parallel12r::nearest_singularity(m, q_);
  endpoint_label_->setText(QString("(%1, %2, %3) %4").arg(number(p.x()), number(p.y()), number(p.z()), unit));
  cond_label_->setText(std::isfinite(c.cond) ? number(c.cond) : tr("∞ (singular)"));
  det_label_->setText(number(c.det));
  singular_label_->setText(QString("%1, %2 %3")
                               .arg(QString::fromUtf8(to_string(s.nearest).data()))
                               .arg(number(s.distance, 3))
                               .arg(unit));
  branch_label_->setText(QString::number(parallel12r::branch_of(q_)));
}

int run_window(const WindowOptions& options, int argc, char** argv) {
  Preset preset = load_preset(options.mechanism.mechanism);
  apply_overrides(preset, options.mechanism.params);
  int width = 0, height = 0;
  if (std::sscanf(options.size.c_str(), "%dx%d", &width, &height) != 2 || width < 200 || height < 150)
    throw std::invalid_argument("--size expects WIDTHxHEIGHT (at least 200x150), got '" + options.size + "'");

  QSurfaceFormat::setDefaultFormat(VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setApplicationName("Linkscape");
  QApplication::setOrganizationName("Linkscape");
  MainWindow window(preset);
  window.resize(width, height);
  window.show();
  if (options.screenshot.empty()) return QApplication::exec();

  // Screenshot mode: wait for the first rendered frame, grab, save, quit.
  int status = 1;
  QObject::connect(window.view(), &VtkWidget::rendered, &window, [&] {
    QTimer::singleShot(50, &window, [&] {
      const QImage image = window.grab().toImage();
      try {  // exceptions must not cross Qt's event loop
        write_atomically(options.screenshot, [&](const std::filesystem::path& tmp) {
          if (!image.save(QString::fromStdString(tmp.string()), "PNG"))
            throw std::runtime_error("cannot write PNG '" + options.screenshot + "'");
        });
        std::cout << "wrote " << options.screenshot << " (" << image.width() << "x" << image.height() << ")\n";
        status = 0;
      } catch (const std::exception& e) {
        std::cerr << "linkscape: error: " << e.what() << "\n";
      }
      QApplication::quit();
    });
  }, Qt::SingleShotConnection);
  QTimer::singleShot(30000, &app, [] {
    std::cerr << "linkscape: no frame was rendered within 30 s\n";
    QApplication::exit(1);
  });
  QApplication::exec();
  return status;
}

}  // namespace linkscape::gui
