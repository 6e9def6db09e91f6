// The device window, driven as a user drives it, for every shipped device:
// task and actuator sliders, design parameters, endpoint drags, sessions,
// the preset chooser, the methods dock and the picture. Numbers are checked
// against the device's own kinematics (core/mechanism.h), not literals.
#include <QCheckBox>
#include <QWindow>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QMessageBox>
#include <QPushButton>
#include <QPointer>
#include <QSignalSpy>
#include <QSlider>
#include <QTemporaryDir>
#include <QThread>
#include <QtTest>
#include <vtkCoordinate.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include <numbers>

#include "core/mechanism.h"
#include "core/mechanisms/pathos2/mechanism.h"
#include "core/preset.h"
#include "gui/window/field_job.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/methods_panel.h"
#include "gui/window/session.h"
#include "gui/window/vtk_widget.h"
#include "render/field_scene.h"
#include "render/skeleton_scene.h"
#include "window_checks.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const char* const kDevices[] = {"parallel-12r", "pathos2"};

void show_fields(MechanismWindow& w, bool slice, bool surfaces) {
  w.findChild<QCheckBox*>("showSliceBox")->setChecked(slice);
  w.findChild<QCheckBox*>("showReachBox")->setChecked(surfaces);
  w.findChild<QCheckBox*>("showWellBox")->setChecked(surfaces);
}

// Shows the window at 1200x800 and waits until its fields (on or off) are computed.
bool show_settled(MechanismWindow& w, bool fields) {
  w.resize(1200, 800);
  w.show();
  if (!QTest::qWaitForWindowExposed(&w)) return false;
  if (!fields) show_fields(w, false, false);
  if (!QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000)) return false;
  QTest::qWait(50);
  return true;
}

// Pixels of the failing-part red (the devices use no other saturated red
// but the handle, which is there before and after).
int red_pixels(const QImage& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QRgb p = image.pixel(x, y);
      if (qRed(p) > 150 && qGreen(p) < 60 && qBlue(p) < 60) ++n;
    }
  return n;
}

double angle_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double d = 0;
  for (Eigen::Index k = 0; k < a.size(); ++k) d = std::max(d, std::abs(std::remainder(a(k) - b(k), 2 * std::numbers::pi)));
  return d;
}

// The IK solution of the window's branch at its task, seeded with its actuators.
Eigen::VectorXd ik_of(const MechanismWindow& w) {
  IkOptions o;
  o.seed = w.actuators();
  if (w.mechanism().info().branches.size() > 1) o.branch = w.branch();
  const IkResult r = w.mechanism().inverse(w.task(), o);
  if (r.solutions.empty() || r.solutions.front().status != Status::Ok) return Eigen::VectorXd();
  return r.solutions.front().q;
}

QDoubleSpinBox* box(MechanismWindow& w, const std::string& name) {
  return w.findChild<QDoubleSpinBox*>(QString::fromStdString(name) + "Box");
}

}  // namespace

class MechanismWindowTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    // A message box would wait for a click: close it and fail with its text.
    auto* timer = new QTimer(this);
    connect(timer, &QTimer::timeout, this, [] {
      if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
        qWarning("message box: %s", qPrintable(box->text()));
        box->reject();
      }
    });
    timer->start(200);
  }
  void init() { QSettings().clear(); }

  void panelsAreBuiltFromTheDescription() {
    for (const char* device : kDevices) {
      MechanismWindow w(load_preset(device));
      const MechanismInfo& info = w.mechanism().info();
      for (const Quantity& p : info.parameters) {
        // In the design dock (a task coordinate may share a parameter's name).
        auto* b = w.findChild<QDockWidget*>("designDock")->findChild<QDoubleSpinBox*>(QString::fromStdString(p.name) + "Box");
        QVERIFY2((b != nullptr) == p.in_panel, p.name.c_str());
        if (b) QVERIFY2(b->toolTip().startsWith(QString::fromStdString(p.description.empty() ? p.name : p.description)),
                        qPrintable(b->toolTip()));
      }
      for (const auto* list : {&info.actuators, &info.task})
        for (const Quantity& q : *list) QVERIFY2(box(w, q.name), q.name.c_str());
      for (const NamedItem& m : info.measures) QVERIFY(w.findChild<QLabel*>(QString::fromStdString(m.name) + "Label"));
      // Field choices from the description; combos hidden where there is nothing to choose.
      const gui::FieldChoices choices = gui::field_choices(info);
      auto* fields = w.findChild<QComboBox*>("fieldBox");
      QCOMPARE(fields->count(), int(choices.fields.size()));
      QCOMPARE(fields->itemText(0), QString::fromStdString(info.measures.front().title));
      QCOMPARE(w.findChild<QComboBox*>("methodBox")->isVisibleTo(&w), info.ik_methods.size() > 1);
      QCOMPARE(w.findChild<QComboBox*>("branchBox")->isVisibleTo(&w), info.branches.size() > 1);
      QCOMPARE(w.findChild<QComboBox*>("fieldBranchBox")->isVisibleTo(&w), info.branches.size() > 1);
    }
  }

  void taskSlidersDriveByInverseKinematics() {
    for (const char* device : kDevices) {
      MechanismWindow w(load_preset(device));
      QVERIFY(show_settled(w, false));
      QCOMPARE(w.drive(), MechanismWindow::Drive::Task);
      const QImage before = frame(w);
      auto* actuators = w.findChild<QLabel*>("actuatorLabel");
      const QString actuators_before = actuators->text();
      const int branch = w.branch();
      // x a little way from home, by the spin box; the slider follows.
      const double x = w.task()(0) + 0.08 * w.mechanism().size();
      box(w, "x")->setValue(x);
      QVERIFY2(w.refusal().isEmpty(), qPrintable(w.refusal()));
      QVERIFY(std::abs(w.task()(0) - box(w, "x")->value()) < 1e-12);
      QCOMPARE(w.branch(), branch);
      // The actuators are the device's IK of the task, and FK gives it back.
      QVERIFY(angle_distance(ik_of(w), w.actuators()) < 1e-9);
      FkOptions fo;
      fo.seed = w.task();
      QVERIFY((w.mechanism().forward(w.actuators(), fo).x - w.task()).norm() < 1e-8);
      QVERIFY(actuators->text() != actuators_before);
      // The picture shows it: the drawn driven point is the task's.
      QVERIFY((w.scene().pose().p_world_endpoint - w.endpoint()).norm() < 1e-9);
      QVERIFY2(changed_fraction(before, frame(w)) > 0.002, device);
      // The slider moves it too.
      auto* slider = w.findChild<QSlider*>("xSlider");
      slider->setValue(slider->value() - 20);
      QVERIFY(std::abs(w.task()(0) - box(w, "x")->value()) < 1e-12);
    }
  }

  void actuatorSlidersDriveByForwardKinematicsThatAgreesWithIk() {
    for (const char* device : kDevices) {
      MechanismWindow w(load_preset(device));
      QVERIFY(show_settled(w, false));
      w.setDrive(MechanismWindow::Drive::Actuators);
      const auto& info = w.mechanism().info();
      QVERIFY(box(w, info.actuators[0].name)->isEnabled());
      QVERIFY(!box(w, "x")->isEnabled());
      const QImage before = frame(w);
      const Eigen::VectorXd x0 = w.task();
      QDoubleSpinBox* first = box(w, info.actuators[0].name);
      QDoubleSpinBox* last = box(w, info.actuators.back().name);
      const double a = first->value() + 6.0, b = last->value() - 4.0;  // degrees
      first->setValue(a);
      last->setValue(b);
      QVERIFY2(w.refusal().isEmpty(), qPrintable(w.refusal()));
      QVERIFY(std::abs(std::remainder(w.actuators()(0) - a * kDeg, 2 * std::numbers::pi)) < 1e-9);
      QVERIFY(std::abs(std::remainder(w.actuators()(w.actuators().size() - 1) - b * kDeg, 2 * std::numbers::pi)) < 1e-9);
      QVERIFY((w.task().head<3>() - x0.head<3>()).norm() > 0.05);
      // FK's pose, solved back by IK in the window's branch, gives the actuators set.
      QVERIFY2(angle_distance(ik_of(w), w.actuators()) < 1e-7, device);
      // The task panel follows, so switching back continues from here.
      QVERIFY(std::abs(box(w, "x")->value() - w.task()(0)) < 0.001);
      QVERIFY2(changed_fraction(before, frame(w)) > 0.002, device);
    }
  }

  void deviceReadoutsAreShown() {
    // PATHOS-II lists its nine-sensor FK beside the numerical one the window drives by.
    MechanismWindow w(load_preset("pathos2"));
    w.setDrive(MechanismWindow::Drive::Actuators);
    Eigen::VectorXd q = w.actuators();
    q(0) += 6 * kDeg;
    q(4) -= 4 * kDeg;
    QVERIFY2(w.setActuators(q), qPrintable(w.refusal()));
    const auto rows = w.mechanism().readouts(w.actuators(), w.task());
    QVERIFY(!rows.empty());
    QStringList texts;
    for (QLabel* l : w.findChildren<QLabel*>()) texts << l->text();
    for (const auto& [label, text] : rows) {
      QVERIFY(texts.contains(QString::fromStdString(label)));
      QVERIFY(texts.contains(QString::fromStdString(text)));
    }
    // The nine-sensor closed form, at the sensors of the pose shown, gives that
    // pose back far below anything visible.
    const pathos2::Geometry g = pathos2::make_geometry(make_pathos2(w.preset()));
    const Eigen::VectorXd& x = w.task();
    const pathos2::Pose pose = pathos2::Pose::from_xyz_rpy(x(0), x(1), x(2), x(3), x(4), x(5), x(6));
    const pathos2::PoseIkResult ik = pathos2::inverse(g, pose);
    QCOMPARE(ik.status, Status::Ok);
    QVERIFY(angle_distance(ik.q_active, w.actuators()) < 1e-9);
    const pathos2::FkResult nine = pathos2::forward_nine_sensors(g, pathos2::sensors_of(ik));
    QCOMPARE(nine.status, Status::Ok);
    QVERIFY((nine.pose.p_world_E - pose.p_world_E).norm() < 1e-6);
    QVERIFY((nine.pose.R_world_E - pose.R_world_E).norm() < 1e-8);
  }

  // The runner goes coarse first only while full passes are slow, and
  // answers a fast slice-only job at once (so the next frame shows it).
  void fieldJobsGoCoarseFirstOnlyWhenFullPassesAreSlow() {
    for (const bool slow : {true, false}) {
      gui::FieldJobRunner runner;
      std::atomic<int> calls{0};
      gui::FieldJob job;
      job.sampler = [&](const Grid& grid, const FieldProgress&) -> std::optional<Field> {
        ++calls;
        if (slow) QThread::msleep(50);
        Field f;
        f.grid = grid;
        return f;
      };
      job.slice = Grid::slice(Axis::X, 0.0, -1, 1, -1, 1, 64, 64);
      QList<bool> passes;  // fine flags, in order
      QObject::connect(&runner, &gui::FieldJobRunner::sliceReady, &runner,
                       [&](const gui::SliceResult& r) { passes << r.fine; });
      for (int round = 0; round < 2; ++round) {
        passes.clear();
        runner.submit(job);
        QVERIFY(QTest::qWaitFor([&] { return !passes.isEmpty() && passes.last(); }, 10000));
        // The first job knows no timing yet: coarse first. Later ones follow the last full pass.
        if (round == 0 || slow) QCOMPARE(passes, (QList<bool>{false, true}));
        else QCOMPARE(passes, QList<bool>{true});
      }
      if (!slow) {
        passes.clear();
        runner.submit(job);
        QCOMPARE(passes, QList<bool>{true});  // answered before submit returned
      }
    }
  }

  void parameterChangeRecomputesFields() {
    for (const char* device : kDevices) {
      MechanismWindow w(load_preset(device));
      QVERIFY(show_settled(w, true));
      QVERIFY(w.fieldScene().slice_visible());
      const std::size_t faces_before = w.fieldScene().surface_faces(render::Surface::Reach);
      QVERIFY(faces_before > 0);
      std::string name;
      for (const Quantity& p : w.mechanism().info().parameters)
        if (p.in_panel && name.empty()) name = p.name;
      const double value = w.mechanism().parameters().at(name);
      QSignalSpy slices(&w, &MechanismWindow::sliceUpdated);
      QSignalSpy updates(&w, &MechanismWindow::fieldsUpdated);
      box(w, name)->setValue(0.6 * value);
      QVERIFY(std::abs(w.mechanism().parameters().at(name) - box(w, name)->value()) < 1e-12);
      QCOMPARE(w.preset().parameters.at(name), w.mechanism().parameters().at(name));
      // The change returned before its fields were computed: they run off the GUI thread.
      QVERIFY(!w.fieldsSettled());
      wait_settled(w);
      // Full resolution last; coarse passes before it only where the last full
      // pass was slow (gui/window/field_job.h; the runner's own test covers both ways).
      QVERIFY(slices.size() >= 1);
      QCOMPARE(slices.last().at(0).toBool(), true);
      for (qsizetype k = 0; k + 1 < slices.size(); ++k) QCOMPARE(slices.at(k).at(0).toBool(), false);
      QCOMPARE(updates.last().at(0).toBool(), true);
      QVERIFY(w.fieldScene().surface_faces(render::Surface::Reach) > 0);
      QVERIFY(w.fieldScene().surface_faces(render::Surface::Reach) != faces_before);
    }
    // 12R: L1 != L2 makes the reachable set a shell: the inner sphere appears.
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    wait_settled(w);
    const std::size_t sphere = w.fieldScene().surface_faces(render::Surface::Reach);
    box(w, "L1")->setValue(8.0);
    QCOMPARE(w.mechanism().parameters().at("L1"), 8.0);
    QCOMPARE(w.mechanism().parameters().at("L2"), 15.0);
    wait_settled(w);
    QVERIFY(w.fieldScene().surface_faces(render::Surface::Reach) > sphere);
  }

  void secondMeasureIsAFieldOnTheSlice() {
    MechanismWindow w(load_preset("pathos2"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    wait_settled(w);
    const auto& measures = w.mechanism().info().measures;
    QCOMPARE(w.fieldScene().colour_bar_title().substr(0, measures[0].title.size()), measures[0].title);
    auto* fields = w.findChild<QComboBox*>("fieldBox");
    fields->setCurrentIndex(fields->findData(QString::fromStdString(measures[1].name)));
    wait_settled(w);  // a field with extra arrays (the stops') is sampled again
    QCOMPARE(w.fieldScene().colour_bar_title().substr(0, measures[1].title.size()), measures[1].title);
  }

  void endpointDragNeverChangesBranch() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    for (int start_branch : {0, 1}) {
      QVERIFY2(w.moveEndpointTo({-12, 16, -8}, start_branch), qPrintable(w.refusal()));
      QCOMPARE(w.branch(), start_branch);
      // A drag across the workspace, through the region where both branches
      // come close to each other (near the z axis and the outer sphere).
      for (int i = 0; i <= 200; ++i) {
        const double t = i / 200.0;
        const Eigen::Vector3d target = Eigen::Vector3d(-12, 16, -8) * (1 - t) + Eigen::Vector3d(14, 4, 22) * t;
        QVERIFY2(w.moveEndpointTo(target), qPrintable(w.refusal()));
        QCOMPARE(w.branch(), start_branch);
        FkOptions fo;
        QVERIFY((w.mechanism().forward(w.actuators(), fo).x - target).norm() < 1e-9);
      }
    }
    // Unreachable: the pose stays, the panel says why.
    const Eigen::VectorXd kept = w.actuators();
    QVERIFY(!w.moveEndpointTo({0, 40, 0}));
    QCOMPARE(w.actuators(), kept);
    QVERIFY2(w.refusal().startsWith("unreachable"), qPrintable(w.refusal()));
    QCOMPARE(w.findChild<QLabel*>("statusLabel")->text(), w.refusal());
    // Singular: on the actuator plane.
    QVERIFY(!w.moveEndpointTo({5, 0, 5}));
    QCOMPARE(w.actuators(), kept);
    QVERIFY2(w.refusal().startsWith("singular"), qPrintable(w.refusal()));
    // A jump across the actuator plane is refused rather than taken.
    QVERIFY(!w.moveEndpointTo({10, -15, 10}));
    QCOMPARE(w.actuators(), kept);
    QVERIFY2(w.refusal().startsWith("jump"), qPrintable(w.refusal()));
    // The branch box moves the device to the other branch at the same point.
    const Eigen::Vector3d d = w.endpoint();
    const int other = 1 - w.branch();
    QVERIFY(w.moveEndpointTo(d, other));
    QCOMPARE(w.branch(), other);
    QVERIFY((w.endpoint() - d).norm() < 1e-12);
    QCOMPARE(w.findChild<QComboBox*>("branchBox")->currentIndex(), other);
  }

  // The drag sent to the view widget (as tests do elsewhere) and to its
  // native window, where a real mouse's events arrive.
  void mouseDragOfTheHandleMovesTheDrivenPoint() {
    for (const char* device : kDevices)
      for (bool native : {false, true}) {
      MechanismWindow w(load_preset(device));
      QVERIFY(show_settled(w, false));
      frame(w);
      vtkRenderer* renderer = w.view()->renderWindow()->GetRenderers()->GetFirstRenderer();
      const Eigen::Vector3d d = w.endpoint();
      vtkNew<vtkCoordinate> c;
      c->SetCoordinateSystemToWorld();
      c->SetValue(d.x(), d.y(), d.z());
      const int* px = c->GetComputedDisplayValue(renderer);  // origin bottom left, device pixels
      const double dpr = w.view()->devicePixelRatioF();
      const QPoint start(int(px[0] / dpr), int(w.view()->height() - px[1] / dpr));
      const int branch = w.branch();
      const Eigen::VectorXd q0 = w.actuators(), x0 = w.task();
      QWindow* window = w.view()->nativeWindow();
      if (native) QTest::mousePress(window, Qt::LeftButton, Qt::NoModifier, start);
      else QTest::mousePress(w.view(), Qt::LeftButton, Qt::NoModifier, start);
      for (int i = 1; i <= 10; ++i) {
        const QPointF p = start + QPoint(0, -3 * i);
        QMouseEvent move(QEvent::MouseMove, p, w.view()->mapToGlobal(p), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
        if (native) QApplication::sendEvent(window, &move);
        else QApplication::sendEvent(w.view(), &move);
        QTest::qWait(10);
      }
      if (native) QTest::mouseRelease(window, Qt::LeftButton, Qt::NoModifier, start + QPoint(0, -30));
      else QTest::mouseRelease(w.view(), Qt::LeftButton, Qt::NoModifier, start + QPoint(0, -30));
      QVERIFY2((w.actuators() - q0).norm() > 1e-3, device);
      QCOMPARE(w.branch(), branch);
      // Moving up on screen raises the driven point; the other task coordinates stay.
      QVERIFY2(w.endpoint().z() > d.z(), device);
      QVERIFY((w.task().tail(w.task().size() - 3) - x0.tail(x0.size() - 3)).norm() < 1e-12);
    }
  }

  void failingPartIsNamedAndDrawnRed() {
    MechanismWindow w(load_preset("pathos2"));
    QVERIFY(show_settled(w, false));
    const Eigen::VectorXd valid = w.task();
    const int red_before = red_pixels(frame(w));
    Eigen::VectorXd far = valid;
    far(2) = 42.0;  // next to the upper base plate
    const IkResult ik = w.mechanism().inverse(far);
    QVERIFY(ik.status != Status::Ok && !ik.failing_part.empty());
    box(w, "z")->setValue(42.0);
    QCOMPARE(w.task(), valid);
    QVERIFY2(w.refusal().startsWith(QString("leg %1: ").arg(QString::fromStdString(ik.failing_part))),
             qPrintable(w.refusal()));
    QCOMPARE(w.failingPart(), QString::fromStdString(ik.failing_part));
    QCOMPARE(w.findChild<QLabel*>("statusLabel")->text(), w.refusal());
    // The failing leg is drawn in red where the user looks.
    const QImage refused = frame(w);
    refused.save(QDir::currentPath() + "/pathos2_refused.png");  // for inspection
    QVERIFY2(red_pixels(refused) > red_before + 200, "the failing leg is not highlighted in the view");
    int failing = 0;
    for (BodyState s : w.scene().pose().states) failing += s == BodyState::Failing;
    QCOMPARE(failing, 3);  // the leg's three links
    // A reachable pose is taken again and clears the message and the red.
    box(w, "z")->setValue(valid(2) + 1.0);
    QVERIFY(w.refusal().isEmpty());
    for (BodyState s : w.scene().pose().states) QCOMPARE(s, BodyState::Normal);
  }

  void sessionRoundTrip() {
    for (const char* device : kDevices) {
      QTemporaryDir dir;
      const QString path = dir.filePath("s.json");
      MechanismWindow w(load_preset(device));
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      std::string name;
      for (const Quantity& p : w.mechanism().info().parameters)
        if (p.in_panel) name = p.name;  // the last one in the panel
      const double value = 0.9 * w.mechanism().parameters().at(name);
      box(w, name)->setValue(value);
      QVERIFY(w.moveEndpointTo(w.endpoint() + Eigen::Vector3d(0.05, -0.03, 0.04) * w.mechanism().size()));
      w.findChild<QComboBox*>("normalBox")->setCurrentText("z");
      w.findChild<QDoubleSpinBox*>("thresholdBox")->setValue(4.0);
      w.findChild<QComboBox*>("fieldBox")->setCurrentIndex(1);
      QVERIFY(w.saveSession(path));

      MechanismWindow other(load_preset(device));
      other.show();
      QVERIFY(QTest::qWaitForWindowExposed(&other));
      QVERIFY(other.openSession(path));
      QCOMPARE(other.mechanism().parameters(), w.mechanism().parameters());
      QCOMPARE(box(other, name)->value(), box(w, name)->value());  // the panel shows it
      QVERIFY((other.task() - w.task()).norm() < 1e-12);
      QVERIFY(angle_distance(other.actuators(), w.actuators()) < 1e-12);
      QCOMPARE(other.branch(), w.branch());
      QCOMPARE(box(other, "x")->value(), box(w, "x")->value());
      QCOMPARE(other.findChild<QComboBox*>("normalBox")->currentText(), QString("z"));
      QCOMPARE(other.findChild<QDoubleSpinBox*>("thresholdBox")->value(), 4.0);
      QCOMPARE(other.findChild<QComboBox*>("fieldBox")->currentIndex(), 1);
      // The camera as saved (w's own, untouched, follows its view's shape since).
      QCOMPARE(other.session().camera->position, gui::load_session(path.toStdString()).camera->position);
      // Recent files remember it; a shipped preset is recorded by name.
      QVERIFY(QSettings().value("recentSessions").toStringList().contains(QFileInfo(path).absoluteFilePath()));
      QCOMPARE(gui::load_session(path.toStdString()).mechanism, std::string(device));
    }
    // A length the window's box cannot show is refused before anything changes.
    MechanismWindow w(load_preset("parallel-12r"));
    const Eigen::VectorXd q = w.actuators();
    gui::Session far = w.session();
    far.parameters["L1"] = 100.0;  // the box spans 1.5 .. 45 cm for this preset
    far.pose = Eigen::VectorXd::Constant(3, 0.3);
    far.task.resize(0);
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, w.applySession(far));
    QCOMPARE(w.mechanism().parameters().at("L1"), 15.0);
    QCOMPARE(box(w, "L1")->value(), 15.0);
    QCOMPARE(w.actuators(), q);
  }

  void olderSessionFilesOpen() {
    // pose_rad: parallel-12r actuators; platform_pose: the PATHOS-II task.
    QTemporaryDir dir;
    const QString twelve = dir.filePath("12r.json"), six = dir.filePath("p2.json");
    QFile f1(twelve), f2(six);
    QVERIFY(f1.open(QIODevice::WriteOnly) && f2.open(QIODevice::WriteOnly));
    f1.write(R"({"format": "linkscape-session", "version": 1, "mechanism": "parallel-12r",
      "parameters": {"L1": 15, "L2": 13}, "pose_rad": [0.1, 0.9, -0.2],
      "field": {"field": "cond", "method": "planar"}})");
    f2.write(R"({"format": "linkscape-session", "version": 1, "mechanism": "pathos2",
      "parameters": {"l2": 14}, "platform_pose": [1, -0.5, 23, 0.05, 0, 0.6, 6.5],
      "field": {"field": "cond_jo", "method": "planar", "volume_resolution": 48, "slice_resolution": 128}})");
    f1.close();
    f2.close();
    MechanismWindow w(load_preset("parallel-12r"));
    w.applySession(gui::load_session(twelve.toStdString()));
    QVERIFY((w.actuators() - Eigen::Vector3d(0.1, 0.9, -0.2)).norm() < 1e-12);
    QCOMPARE(w.mechanism().parameters().at("L2"), 13.0);
    MechanismWindow p(load_preset("pathos2"));
    p.applySession(gui::load_session(six.toStdString()));
    Eigen::VectorXd expected(7);
    expected << 1, -0.5, 23, 0.05, 0, 0.6, 6.5;
    QVERIFY((p.task() - expected).norm() < 1e-12);
    QCOMPARE(p.mechanism().parameters().at("l2"), 14.0);
    QCOMPARE(p.findChild<QComboBox*>("fieldBox")->currentData().toString(), QString("cond_jo"));
    QCOMPARE(p.findChild<QComboBox*>("sliceResolutionBox")->currentText(), QString("128"));
  }

  void aSessionOfAnotherDeviceReplacesTheWindow() {
    QTemporaryDir dir;
    const QString path = dir.filePath("12r.json");
    MechanismWindow twelve(load_preset("parallel-12r"));
    QVERIFY(twelve.saveSession(path));
    auto* p2 = new MechanismWindow(load_preset("pathos2"));
    p2->setAttribute(Qt::WA_DeleteOnClose);
    p2->show();
    QVERIFY(QTest::qWaitForWindowExposed(p2));
    QPointer<MechanismWindow> guard(p2);
    QVERIFY(p2->openSession(path));
    QTRY_VERIFY(guard.isNull() || !guard->isVisible());
    MechanismWindow* opened = nullptr;
    for (QWidget* top : QApplication::topLevelWidgets())
      if (auto* m = qobject_cast<MechanismWindow*>(top); m && m != &twelve && m->isVisible()) opened = m;
    QVERIFY(opened);
    QCOMPARE(opened->mechanism().info().name, twelve.mechanism().info().name);
    QVERIFY(angle_distance(opened->actuators(), twelve.actuators()) < 1e-12);
    opened->close();
  }

  void presetChooserSwitchesTheDeviceKeepingFieldSettings() {
    auto* w = new MechanismWindow(load_preset("parallel-12r"));
    w->setAttribute(Qt::WA_DeleteOnClose);
    w->show();
    QVERIFY(QTest::qWaitForWindowExposed(w));
    w->findChild<QComboBox*>("normalBox")->setCurrentText("z");
    w->findChild<QDoubleSpinBox*>("thresholdBox")->setValue(4.5);
    w->findChild<QCheckBox*>("showWellBox")->setChecked(false);
    QPointer<MechanismWindow> guard(w);
    auto* chooser = w->findChild<QComboBox*>("presetBox");
    const int index = chooser->findText("pathos2");
    QVERIFY(index >= 0);
    chooser->setCurrentIndex(index);
    emit chooser->activated(index);
    QTRY_VERIFY(guard.isNull() || !guard->isVisible());  // replaced, not stacked
    MechanismWindow* opened = nullptr;
    for (QWidget* top : QApplication::topLevelWidgets())
      if (auto* m = qobject_cast<MechanismWindow*>(top); m && m->isVisible()) opened = m;
    QVERIFY(opened);
    QCOMPARE(opened->mechanism().info().name, std::string("pathos2"));
    QVERIFY(opened->findChild<QDoubleSpinBox*>("l2Box"));  // its own panels
    QVERIFY(!opened->findChild<QDoubleSpinBox*>("L1Box"));
    QCOMPARE(opened->findChild<QComboBox*>("normalBox")->currentText(), QString("z"));
    QCOMPARE(opened->findChild<QDoubleSpinBox*>("thresholdBox")->value(), 4.5);
    QVERIFY(!opened->findChild<QCheckBox*>("showWellBox")->isChecked());
    opened->close();
  }

  void methodsDockMeasuresTheCurrentDesign() {
    for (const char* device : kDevices) {
      MechanismWindow w(load_preset(device));
      w.resize(1280, 800);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      std::string name;
      for (const Quantity& p : w.mechanism().info().parameters)
        if (p.in_panel && name.empty()) name = p.name;
      const double value = 0.8 * w.mechanism().parameters().at(name);
      QVERIFY(w.setParameters({{name, value}}));
      auto* panel = w.findChild<gui::MethodsPanel*>();
      QVERIFY(panel);
      w.findChild<QDockWidget*>("methodsDock")->raise();
      panel->setHarnessSize(100, 1);
      QSignalSpy finished(panel, &gui::MethodsPanel::runFinished);
      panel->run();
      QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 1, 120000);
      QVERIFY(finished.front().front().toBool());
      QVERIFY(!panel->rows().empty());
      for (const auto& r : panel->rows()) QCOMPARE(r.mechanism, w.mechanism().info().name);
      // The run measured the window's design, not the preset's.
      QCOMPARE(panel->mechanism().parameters.at(name), value);
      QCOMPARE(box(w, name)->value(), w.mechanism().parameters().at(name));
    }
  }

  void actuatorLimitsBoundTheSlidersAndThePose() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.setDrive(MechanismWindow::Drive::Actuators);
    QVERIFY(w.setActuators(Eigen::Vector3d(20 * kDeg, 65 * kDeg, 5 * kDeg)));
    QVERIFY(w.setActuatorLimits({{"alpha", {-10, 10}}}));
    QCOMPARE(w.findChild<QDoubleSpinBox*>("alphaBox")->maximum(), 10.0);
    QCOMPARE(w.findChild<QDoubleSpinBox*>("alphaMaxBox")->value(), 10.0);
    QVERIFY(std::abs(w.actuators()(0) - 10 * kDeg) < 1e-12);  // the pose is clamped into the range
    QCOMPARE(w.mechanism().info().actuators[0].range.hi, 10 * kDeg);
    // An inverted range is refused; the limits in force stay, and the boxes show them.
    QVERIFY(!w.setActuatorLimits({{"alpha", {5, -5}}}));
    QCOMPARE(w.mechanism().info().actuators[0].range.hi, 10 * kDeg);
    QCOMPARE(w.findChild<QDoubleSpinBox*>("alphaMinBox")->value(), -10.0);
    // Sessions keep them.
    MechanismWindow other(load_preset("parallel-12r"));
    other.applySession(w.session());
    QCOMPARE(other.findChild<QDoubleSpinBox*>("alphaBox")->maximum(), 10.0);
    QCOMPARE(other.mechanism().info().actuators[0].range.lo, -10 * kDeg);
    // PATHOS-II takes no actuator limits: no boxes for them.
    MechanismWindow p(load_preset("pathos2"));
    QVERIFY(!p.findChild<QDoubleSpinBox*>("q1MaxBox"));
  }

  void animationFollowsACircleInOneBranch() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    QVERIFY(w.moveEndpointTo({-12, 16, -8}, 0));
    const int branch = w.branch();
    const Eigen::Vector3d d0 = w.endpoint();
    auto* play = w.findChild<QPushButton*>("playButton");
    play->setChecked(true);
    QTest::qWait(600);
    play->setChecked(false);
    const Eigen::Vector3d d1 = w.endpoint();
    QVERIFY((d1 - d0).norm() > 0.5);
    QCOMPARE(w.branch(), branch);
    // The circle lies in the slice plane (normal x): x does not change.
    QVERIFY(std::abs(d1.x() - d0.x()) < 1e-9);
  }

  void surfacesAreLightOnlyWhileSomethingIsDragged() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w, true));
    w.setDrive(MechanismWindow::Drive::Actuators);
    const render::FieldScene& scene = w.fieldScene();
    QVERIFY(scene.surface_visible(render::Surface::Reach));
    QVERIFY(!scene.drawing_light(render::Surface::Reach));
    auto* slider = w.findChild<QSlider*>(QString::fromStdString(w.mechanism().info().actuators.at(1).name) + "Slider");
    QVERIFY(slider);
    slider->setSliderDown(true);  // the light meshes are made now, off the GUI thread
    QTRY_VERIFY_WITH_TIMEOUT(scene.drawing_light(render::Surface::Reach), 10000);
    QVERIFY(scene.drawing_light(render::Surface::WellConditioned));
    slider->setValue(slider->value() + 20);
    QVERIFY(scene.drawing_light(render::Surface::Reach));
    slider->setSliderDown(false);
    QVERIFY(!scene.drawing_light(render::Surface::Reach));
    QVERIFY(!scene.drawing_light(render::Surface::WellConditioned));
    QVERIFY(scene.surface_visible(render::Surface::Reach));
    // Turning the camera: light while the button is down (the meshes are made already).
    const QPoint corner(12, 12);  // away from the device and its handle
    QTest::mousePress(w.view(), Qt::LeftButton, Qt::NoModifier, corner);
    QMouseEvent move(QEvent::MouseMove, QPointF(corner + QPoint(30, 10)), w.view()->mapToGlobal(QPointF(corner + QPoint(30, 10))),
                     Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(w.view(), &move);
    QVERIFY(scene.drawing_light(render::Surface::Reach));
    QTest::mouseRelease(w.view(), Qt::LeftButton, Qt::NoModifier, corner + QPoint(30, 10));
    QVERIFY(!scene.drawing_light(render::Surface::Reach));
  }

  void pictureMatchesBaselines() {
    {
      MechanismWindow w(load_preset("parallel-12r"));
      w.resize(1100, 760);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      w.setDrive(MechanismWindow::Drive::Actuators);
      QVERIFY(w.setActuators(Eigen::Vector3d(20 * kDeg, 65 * kDeg, 5 * kDeg)));
      show_fields(w, false, false);
      wait_settled(w);
      compare_with_baseline(frame(w), "linkage", 10.0);
      show_fields(w, true, true);
      wait_settled(w);
      compare_with_baseline(frame(w), "linkage_and_fields", 10.0);
      // Near a singular pose: alpha close to 90 degrees.
      show_fields(w, false, false);
      QVERIFY(w.setActuators(Eigen::Vector3d(85 * kDeg, 40 * kDeg, -30 * kDeg)));
      compare_with_baseline(frame(w), "near_singular", 10.0);
    }
    // The baseline is the paper's linkage: the preset's assumed stops off.
    Preset pathos2 = load_preset("pathos2");
    pathos2.checks = {false, false};
    MechanismWindow w(pathos2);
    QVERIFY(show_settled(w, true));
    compare_with_baseline(frame(w), "pathos2_home", 10.0);
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("LinkscapeTests");
  QApplication::setApplicationName("gui_tests");
  MechanismWindowTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_mechanism_window.moc"
