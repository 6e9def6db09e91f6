#include "gui/window/task_panel.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QStringList>
#include <QTimer>
#include <QVBoxLayout>
#include <cmath>
#include <sstream>

#include <vtkCellArray.h>
#include <vtkFeatureEdges.h>
#include <vtkIdList.h>
#include <vtkPolyData.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRendererCollection.h>

#include "core/fit.h"
#include "core/verify/verify.h"
#include "gui/window/background.h"
#include "gui/window/vtk_widget.h"
#include "render/task_scene.h"
#include "render/verify_regions.h"

namespace linkscape::gui {
namespace {

constexpr int kSurfaceResolution = 24;  // latitude bands of the drawn sphere, grid of each box face
constexpr double kFlattened = 0.02;        // a planar task drawn as a slab this thin (of its height)

// A planar device's task is its section by the plane (as fit takes it):
// the half of its surface above the plane, flattened onto it (both halves
// would lie one in the other and show each other's facets through).
vtkSmartPointer<vtkPolyData> on_plane(vtkSmartPointer<vtkPolyData> surface, std::optional<double> plane) {
  if (!plane) return surface;
  std::vector<bool> above(std::size_t(surface->GetNumberOfPoints()));
  const double tolerance = 1e-9 * surface->GetLength();  // of its size: the plane may be z = 0
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i) {
    double p[3];
    surface->GetPoint(i, p);
    above[std::size_t(i)] = p[2] >= *plane - tolerance;
    surface->GetPoints()->SetPoint(i, p[0], p[1], *plane + kFlattened * (p[2] - *plane));
  }
  vtkNew<vtkCellArray> kept;
  vtkNew<vtkIdList> cell;
  vtkCellArray* polys = surface->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(cell);) {
    bool keep = true;
    for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k) keep = keep && above[std::size_t(cell->GetId(k))];
    if (keep) kept->InsertNextCell(cell);
  }
  surface->SetPolys(kept);
  return surface;
}

QString number(double v) {
  if (std::isnan(v)) return "n/a";
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-inf";
  return QString::number(v, 'g', 4);
}

// To 1e-4 of the device's size: a centroid of samples carries their
// rounding (-0.00016 for 0), which would read as a position.
QString point_text(const Eigen::Vector3d& p, const QString& unit, double size) {
  const double quantum = 1e-4 * size;
  const auto rounded = [&](double v) { return number(std::round(v / quantum) * quantum + 0.0); };
  return QString("(%1, %2, %3) %4").arg(rounded(p.x()), rounded(p.y()), rounded(p.z()), unit);
}

QDoubleSpinBox* length_box(QWidget* parent) {
  auto* box = new QDoubleSpinBox(parent);
  box->setRange(-1e4, 1e4);
  box->setDecimals(2);
  box->setSingleStep(0.5);
  box->setKeyboardTracking(false);
  box->setMinimumWidth(56);  // three in a row (with their axis labels) fit a narrow dock
  return box;
}

}  // namespace

QString centre_from_home_text(const Eigen::Vector3d& centre, const Eigen::Vector3d& home, double size,
                              const QString& unit) {
  QStringList d;
  for (int k = 0; k < 3; ++k) {
    const double v = centre(k) - home(k);
    d << number(std::abs(v) < 1e-12 * size ? 0.0 : v);
  }
  return QString("centre = home + (%1) %2").arg(d.join(", "), unit);
}

TaskPanel::TaskPanel(render::TaskScene* scene, QWidget* parent) : QWidget(parent), scene_(scene) {
  auto* column = new QVBoxLayout(this);
  auto* form = new QFormLayout;
  column->addLayout(form);
  show_box_ = new QCheckBox(tr("Show the task volume"), this);
  show_box_->setObjectName("taskShowBox");
  show_box_->setToolTip(tr("Draw the task volume in the view, coloured where it leaves the good region"));
  form->addRow(show_box_);
  shape_box_ = new QComboBox(this);
  shape_box_->setObjectName("taskShapeBox");
  shape_box_->setToolTip(tr("A sphere (its diameter) or an axis-aligned box (its sides)"));
  shape_box_->addItems({"sphere", "box"});
  form->addRow(tr("Shape"), shape_box_);
  auto* sizes = new QHBoxLayout;
  auto* centres = new QHBoxLayout;
  for (int k = 0; k < 3; ++k) {
    size_[k] = length_box(this);
    size_[k]->setMinimum(0.01);
    size_[k]->setObjectName(QString("taskSize%1").arg("XYZ"[k]));
    size_[k]->setToolTip(k == 0 ? tr("Diameter of the sphere, or the box's side along x") : tr("The box's side along %1").arg(QChar("xyz"[k])));
    sizes->addWidget(size_[k]);
    centre_[k] = length_box(this);
    centre_[k]->setObjectName(QString("taskCentre%1").arg("XYZ"[k]));
    centre_[k]->setToolTip(tr("The task's centre, %1 in the base frame").arg(QChar("xyz"[k])));
    // Each box named by its axis (the unit is its suffix, and the row's label).
    auto* axis = new QLabel(QString(QChar("xyz"[k])), this);
    axis->setObjectName(QString("taskCentreLabel%1").arg("XYZ"[k]));
    axis->setBuddy(centre_[k]);
    centres->addWidget(axis);
    centres->addWidget(centre_[k], 1);
  }
  size_label_ = new QLabel(this);
  form->addRow(size_label_, sizes);
  centre_label_ = new QLabel(tr("Centre"), this);
  centre_label_->setObjectName("taskCentreRowLabel");
  form->addRow(centre_label_, centres);
  criteria_edit_ = new QLineEdit("cond<3", this);
  criteria_edit_->setObjectName("taskCriteriaEdit");
  criteria_edit_->setPlaceholderText(tr("e.g. cond<3, force_iso>0.5 (separated by commas, semicolons or spaces)"));
  criteria_edit_->setToolTip(tr("Separated by commas, semicolons or spaces, as the command line's --criterion takes "
                                "them: cond<T, cond_jo<T, force_iso>F, force_max>F (N), resolution<R (mm), "
                                "inertia<M (kg); reach is always implied"));
  form->addRow(tr("Criteria"), criteria_edit_);
  place_button_ = new QPushButton(tr("Place at the largest"), this);
  place_button_->setObjectName("taskPlaceButton");
  place_button_->setToolTip(tr("Find the largest sphere (or box of this shape) where every criterion holds, draw it "
                               "and centre the task in it"));
  column->addWidget(place_button_);
  readout_label_ = new QLabel(this);
  readout_label_->setObjectName("taskReadout");
  readout_label_->setWordWrap(true);
  readout_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  readout_label_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  column->addWidget(readout_label_);
  verify_button_ = new QPushButton(tr("Verify (certified)"), this);
  verify_button_->setObjectName("taskVerifyButton");
  verify_button_->setToolTip(tr("Prove by interval arithmetic that every point of the task meets every criterion, "
                                "or find a point that fails; the 12R, the Delta and described devices with crank-rod, "
                                "slide-rod or extensible legs, IK branch 0 "
                                "(docs/task-volumes.md, \"Certified verdicts\")"));
  column->addWidget(verify_button_);
  verdict_label_ = new QLabel(this);
  verdict_label_->setObjectName("taskVerdict");
  verdict_label_->setWordWrap(true);
  verdict_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  column->addWidget(verdict_label_);
  verifier_ = std::make_unique<BackgroundTask>(this, [this] { verify_button_->setText(tr("Verify (certified)")); });
  regions_ = std::make_unique<render::VerifyRegions>();
  column->addStretch(1);

  debounce_ = new QTimer(this);
  debounce_->setSingleShot(true);
  debounce_->setInterval(40);
  connect(debounce_, &QTimer::timeout, this, &TaskPanel::evaluateNow);
  connect(show_box_, &QCheckBox::toggled, this, [this](bool on) {
    scene_->set_visible(on);
    if (on) schedule();
    emit changed();
  });
  connect(shape_box_, &QComboBox::currentIndexChanged, this, [this] {
    syncShape();
    largest_.reset();
    scene_->set_inscribed(nullptr);
    schedule();
  });
  for (QDoubleSpinBox* box : {size_[0], size_[1], size_[2], centre_[0], centre_[1], centre_[2]})
    connect(box, &QDoubleSpinBox::valueChanged, this, &TaskPanel::schedule);
  connect(criteria_edit_, &QLineEdit::editingFinished, this, [this] {
    largest_.reset();
    scene_->set_inscribed(nullptr);
    schedule();
  });
  connect(place_button_, &QPushButton::clicked, this, &TaskPanel::placeAtLargest);
  connect(verify_button_, &QPushButton::clicked, this, &TaskPanel::verifyTask);
  syncShape();
}

TaskPanel::~TaskPanel() {
  if (verifier_) verifier_->cancel();  // the worker stops at its next box and is joined
}

void TaskPanel::verifyTask() {
  if (verifier_->running()) {
    verifier_->cancel();
    return;
  }
  task::TaskVolume volume;
  std::vector<task::Criterion> criteria;
  try {
    volume = this->volume();
    criteria = this->criteria();
  } catch (const std::exception& e) {
    verdict_label_->setStyleSheet("color: #b71c1c");
    verdict_label_->setText(QString::fromStdString(e.what()));
    return;
  }
  verdict_label_->setStyleSheet("");
  verdict_label_->setText(tr("Verifying…"));
  verify_button_->setText(tr("Cancel verify"));
  regions_->clear();
  verifier_->start([this, preset = preset_, volume, criteria](const BackgroundTask::Run& run) {
    verify::Options options;
    options.cancel = &run.cancelled;
    options.time_limit_seconds = 60;
    options.keep_boxes = true;  // drawn in the view
    std::string text, colour;
    auto result = std::make_shared<std::optional<verify::Result>>();
    try {
      const verify::Result r = verify::verify(preset, volume, criteria, options, 0);
      std::ostringstream report;
      verify::write_report(report, r);
      text = report.str();
      colour = r.verdict == verify::Verdict::Proved      ? "#1b5e20"
               : r.verdict == verify::Verdict::Disproved ? "#b71c1c"
                                                         : "#8d6e00";
      if (run.cancelled) text = "cancelled: " + text;
      *result = r;
    } catch (const std::exception& e) {
      text = e.what();
      colour = "#b71c1c";
    }
    run.finish([this, text, colour, result, size = volume.size.maxCoeff()] {
      verdict_label_->setStyleSheet(QString::fromStdString("color: " + colour));
      verdict_label_->setText(QString::fromStdString(text).trimmed());
      if (*result) showRegions(**result, size);
    });
  });
}

void TaskPanel::showRegions(const verify::Result& result, double task_size) {
  // The window's view: its scene renderer is the first (VtkWidget::addRenderers).
  if (auto* view = window()->findChild<VtkWidget*>()) {
    if (vtkRenderer* scene = view->renderWindow()->GetRenderers()->GetFirstRenderer()) regions_->add_to(scene);
  }
  regions_->show(result, 0.03 * task_size);
  emit changed();
}

void TaskPanel::syncShape() {
  const bool sphere = shape_box_->currentIndex() == 0;
  size_label_->setText(sphere ? tr("Diameter") : tr("Size x, y, z"));
  size_[1]->setVisible(!sphere);
  size_[2]->setVisible(!sphere);
  place_button_->setText(sphere ? tr("Place at the largest sphere") : tr("Place at the largest box"));
}

void TaskPanel::setDevice(std::shared_ptr<const Mechanism> mechanism, const Preset& preset, const Eigen::VectorXd& task) {
  const bool new_device = mechanism != mechanism_;
  const bool held_changed = pose_.size() != task.size() || (pose_.tail(task.size() - 3) - task.tail(task.size() - 3)).norm() > 0;
  mechanism_ = std::move(mechanism);
  preset_ = preset;
  pose_ = task;
  if (!centred_) {
    // A first task: at the home point, a quarter of the device's size across.
    const QSignalBlocker b0(size_[0]), b1(size_[1]), b2(size_[2]), c0(centre_[0]), c1(centre_[1]), c2(centre_[2]);
    const double size = 0.25 * mechanism_->size();
    for (int k = 0; k < 3; ++k) {
      size_[k]->setValue(size);
      centre_[k]->setValue(mechanism_->home_task()(k));
      size_[k]->setSuffix(" " + QString::fromStdString(mechanism_->info().length_unit));
      centre_[k]->setSuffix(" " + QString::fromStdString(mechanism_->info().length_unit));
    }
    centre_label_->setText(tr("Centre (%1)").arg(QString::fromStdString(mechanism_->info().length_unit)));
    centred_ = true;
  }
  // A planar device's task is its section by its plane: z is the plane's.
  const std::optional<double> plane = mechanism_->info().plane_z;
  centre_[2]->setEnabled(!plane);
  if (plane) {
    const QSignalBlocker b(centre_[2]);
    centre_[2]->setValue(*plane);
  }
  centre_[2]->setToolTip(plane ? tr("A planar device's task is its section by its plane, z = %1").arg(*plane)
                               : tr("The task's centre, z in the base frame"));
  // Fine enough to hold a centre fit places (fit::centre_step) exactly.
  const int decimals = std::max(2, int(std::lround(-std::log10(fit::centre_step(mechanism_->size())))));
  for (QDoubleSpinBox* box : centre_) {
    const QSignalBlocker b(box);
    box->setDecimals(std::max(decimals, box->decimals()));  // never coarser: a centre set stays as set
  }
  if (new_device) {
    largest_.reset();
    scene_->set_inscribed(nullptr);
  }
  if (new_device || held_changed) schedule();
}

void TaskPanel::setCentre(const Eigen::Vector3d& centre) {
  for (int k = 0; k < 3; ++k) centre_[k]->setValue(centre(k));
}

void TaskPanel::setTask(const std::string& text, const std::vector<std::string>& criteria_texts) {
  const task::TaskVolume t = task::parse_task(text);
  std::string joined;
  for (const std::string& text : criteria_texts)
    for (const std::string& c : task::split_criteria(text)) {
      task::parse_criterion(c);
      joined += (joined.empty() ? "" : ", ") + c;
    }
  {
    const QSignalBlocker b(shape_box_);
    shape_box_->setCurrentIndex(t.shape == task::Shape::Sphere ? 0 : 1);
  }
  syncShape();
  for (int k = 0; k < 3; ++k) {
    const QSignalBlocker b(size_[k]);
    size_[k]->setValue(t.size(k));
  }
  if (!joined.empty()) criteria_edit_->setText(QString::fromStdString(joined));
  this->criteria();  // throws for a measure the device does not know
  if (t.centre)
    for (int k = 0; k < 3; ++k) {
      const QSignalBlocker b(centre_[k]);
      centre_[k]->setValue((*t.centre)(k));
    }
  show_box_->setChecked(true);
  if (!t.centre) placeAtLargest();
  evaluateNow();
}

TaskSetting TaskPanel::setting() const {
  TaskSetting s;
  s.volume = task::to_text(volume());
  s.criteria = task::split_criteria(criteria_edit_->text().toStdString());
  s.shown = show_box_->isChecked();
  return s;
}

void TaskPanel::applySetting(const TaskSetting& s) {
  setTask(s.volume, s.criteria);  // the centre is in the text: no search
  if (s.criteria.empty()) criteria_edit_->clear();
  show_box_->setChecked(s.shown);
}

task::TaskVolume TaskPanel::volume() const {
  task::TaskVolume t;
  t.shape = shape_box_->currentIndex() == 0 ? task::Shape::Sphere : task::Shape::Box;
  t.size = t.shape == task::Shape::Sphere ? Eigen::Vector3d::Constant(size_[0]->value())
                                          : Eigen::Vector3d(size_[0]->value(), size_[1]->value(), size_[2]->value());
  t.centre = Eigen::Vector3d(centre_[0]->value(), centre_[1]->value(), centre_[2]->value());
  return t;
}

std::vector<task::Criterion> TaskPanel::criteria() const {
  std::vector<task::Criterion> out = {task::parse_criterion("reach")};
  for (const std::string& word : task::split_criteria(criteria_edit_->text().toStdString()))
    if (word != "reach") out.push_back(task::parse_criterion(word));
  return task::resolve(device(), out);
}

task::Device TaskPanel::device() const {
  task::Device d;
  d.mechanism = mechanism_;
  d.fixed_task = pose_;
  // Haptic criteria need the preset's actuator data; others do not, so a
  // preset without a physical length unit still evaluates c(J).
  try {
    d.data = haptics::device_data(preset_, mechanism_->info());
  } catch (const std::invalid_argument&) {
  }
  return d;
}

void TaskPanel::schedule() {
  if (show_box_->isChecked()) debounce_->start();
  if (!verifier_->running() && !verdict_label_->text().isEmpty()) {  // a verdict is about what was verified
    verdict_label_->setStyleSheet("color: gray");
    verdict_label_->setText(tr("The design, pose or task changed since the last Verify."));
    regions_->clear();
  }
}

void TaskPanel::evaluateNow() {
  debounce_->stop();
  if (!mechanism_ || !show_box_->isChecked()) return;
  try {
    const std::vector<task::Criterion> c = criteria();
    task::TaskVolume t = volume();
    const task::Device d = device();
    // A planar device's task: centred on the plane, its surface flattened
    // onto it (task::evaluate_point takes a point's z as the plane's).
    const std::optional<double> plane = mechanism_->info().plane_z;
    if (plane) t.centre->z() = *plane;
    report_ = task::evaluate(d, c, t, *t.centre, task::kTaskResolution);  // fit's evaluation: one verdict
    const vtkSmartPointer<vtkPolyData> surface = on_plane(render::task_surface(t, *t.centre, kSurfaceResolution), plane);
    std::vector<std::uint8_t> meets(std::size_t(surface->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i) {
      Eigen::Vector3d p;
      surface->GetPoint(i, p.data());
      meets[std::size_t(i)] = task::evaluate_point(d, c, p).meets;
    }
    scene_->set_task(surface, meets);
    readout_label_->setStyleSheet("");
    readout_label_->setText(readout());
  } catch (const std::invalid_argument& e) {
    report_.reset();
    readout_label_->setStyleSheet("color: #b71c1c");
    readout_label_->setText(QString::fromStdString(e.what()));
  }
  emit changed();
}

QString TaskPanel::readout() const {
  if (!report_ || !mechanism_) return {};
  const task::TaskReport& r = *report_;
  const QString unit = QString::fromStdString(mechanism_->info().length_unit);
  const auto at = [&](const Eigen::Vector3d& p) { return point_text(p, unit, mechanism_->size()); };
  QString text;
  // The words of fit's report (task::verdict_text), at its resolution.
  QString verdict = QString::fromStdString(task::verdict_text(r)).toHtmlEscaped();
  verdict[0] = verdict[0].toUpper();
  text = QString("<b style='color:%1'>%2</b>").arg(r.meets() ? "#1b5e20" : "#b71c1c", verdict);
  if (const std::optional<Eigen::Vector3d> centre = volume().centre) {
    const Eigen::Vector3d home = mechanism_->home_task().head<3>();
    text += "<br>" + centre_from_home_text(*centre, home, mechanism_->size(), unit) +
            tr(", the home point at %1").arg(at(home));
  }
  for (const task::CriterionReport& c : r.criteria) {
    const std::string unit_text = task::criterion_unit(c.criterion, mechanism_->info().length_unit);
    const QString u = unit_text.empty() ? QString() : " " + QString::fromStdString(unit_text);
    // A sample out of reach has no value: said so, not as an infinite worst.
    const QString worst = std::isfinite(c.worst) ? tr("worst %1%2, margin %3%2").arg(number(c.worst), u, number(c.margin()))
                                                 : tr("worst out of reach");
    text += tr("<br>%1: %2, %3")
                .arg(QString::fromStdString(c.criterion.text).toHtmlEscaped(), worst,
                     QString::fromStdString(task::samples_text(r.samples - c.failing, r.samples)));
  }
  if (r.failing > 0)
    text += tr("<br>fails at %1 of %2 samples, around %3").arg(r.failing).arg(r.samples).arg(at(r.failing_centroid));
  if (largest_) {
    if (!largest_->found) text += tr("<br>no sample of the box meets every criterion");
    else if (shape_box_->currentIndex() == 0)
      text += tr("<br>largest sphere: %1 %2 across at %3").arg(number(largest_->size), unit, at(largest_->centre));
    else
      text += tr("<br>largest box: %1 times this one at %2").arg(number(largest_->size), at(largest_->centre));
  }
  return text;
}

void TaskPanel::placeAtLargest() {
  if (!mechanism_) return;
  {
    const QSignalBlocker b(show_box_);  // shown below, once placed
    show_box_->setChecked(true);
    scene_->set_visible(true);
  }
  try {
    const task::TaskVolume t = volume();
    QApplication::setOverrideCursor(Qt::WaitCursor);
    const auto found = task::largest_inscribed(device(), criteria(), t, mechanism_->default_box());
    QApplication::restoreOverrideCursor();
    largest_ = *found;
    if (found->found) {
      task::TaskVolume shape = t;
      shape.size = t.shape == task::Shape::Sphere ? Eigen::Vector3d::Constant(found->size) : Eigen::Vector3d(found->size * t.size);
      const std::optional<double> plane = mechanism_->info().plane_z;
      vtkSmartPointer<vtkPolyData> surface = on_plane(render::task_surface(shape, found->centre, kSurfaceResolution / 2), plane);
      if (plane) {  // in the plane, its outline (its facets would be a web of spokes)
        vtkNew<vtkFeatureEdges> edges;
        edges->SetInputData(surface);
        edges->BoundaryEdgesOn();
        edges->FeatureEdgesOff();
        edges->NonManifoldEdgesOff();
        edges->ManifoldEdgesOff();
        edges->Update();
        surface = edges->GetOutput();
      }
      scene_->set_inscribed(surface);
      for (int k = 0; k < 3; ++k) {
        const QSignalBlocker b(centre_[k]);
        centre_[k]->setValue(found->centre(k));
      }
    }
  } catch (const std::invalid_argument& e) {
    QApplication::restoreOverrideCursor();
    readout_label_->setStyleSheet("color: #b71c1c");
    readout_label_->setText(QString::fromStdString(e.what()));
    return;
  }
  evaluateNow();
}

}  // namespace linkscape::gui
