#include "gui/window/methods_panel.h"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include <exception>
#include <stdexcept>

#include "core/mechanism.h"
#include "gui/window/methods_view.h"

namespace linkscape::gui {
namespace {

QString mechanism_title(const Preset& preset) {
  return QString::fromStdString(preset.title.empty() ? preset.mechanism : preset.title);
}

}  // namespace

MethodsPanel::MethodsPanel(QWidget* parent) : QWidget(parent), task_(this, [this] { cancel_button_->setEnabled(false); }) {
  preset_ = load_preset(default_mechanism());
  auto* layout = new QVBoxLayout(this);
  auto* bar = new QHBoxLayout;
  run_button_ = new QPushButton("Run", this);
  run_button_->setObjectName("run");
  run_button_->setToolTip("Measure time per evaluation and error of every method for the current parameters");
  cancel_button_ = new QPushButton("Cancel", this);
  cancel_button_->setObjectName("cancel");
  cancel_button_->setToolTip(tr("Stop the measurement at its next stage"));
  cancel_button_->setEnabled(false);
  status_ = new QLabel("Not measured yet.", this);
  status_->setObjectName("status");
  status_->setWordWrap(true);  // the whole message, on as many lines as it needs
  auto* enlarge = new QPushButton("Enlarge", this);
  enlarge->setObjectName("enlarge");
  enlarge->setToolTip("Open the chart and the table in a window of their own");
  // A second device measured beside this one: a described device against the
  // compiled one it copies (docs/described-mechanisms.md), or any two presets.
  compare_ = new QComboBox(this);
  compare_->setObjectName("compare");
  compare_->setToolTip("Measure a second preset beside this device; the chart shows both side by side");
  compare_->setSizeAdjustPolicy(QComboBox::AdjustToMinimumContentsLengthWithIcon);
  compare_->setMinimumContentsLength(8);  // narrow panels keep every control in view
  compare_->addItem("compare with: none", QString());
  for (const std::string& name : available_presets())
    compare_->addItem("compare with: " + QString::fromStdString(name), QString::fromStdString(name));
  bar->addWidget(run_button_);
  bar->addWidget(cancel_button_);
  bar->addWidget(compare_);
  bar->addStretch(1);
  bar->addWidget(enlarge);
  layout->addLayout(bar);
  layout->addWidget(status_);
  view_ = new MethodsView(this);
  layout->addWidget(view_, 1);
  connect(enlarge, &QPushButton::clicked, this, &MethodsPanel::enlarge);
  connect(run_button_, &QPushButton::clicked, this, &MethodsPanel::run);
  connect(cancel_button_, &QPushButton::clicked, this, &MethodsPanel::cancel);
}

MethodsPanel::~MethodsPanel() = default;  // the task cancels and joins a run in flight

const std::vector<methods::MethodRow>& MethodsPanel::rows() const { return view_->rows(); }

void MethodsPanel::enlarge() {
  if (!enlarged_) {
    enlarged_ = new MethodsWindow(this);
    enlarged_->setRows(view_->rows(), measured_title_);
    enlarged_->view()->setFamily(view_->family());
  }
  enlarged_->show();
  enlarged_->raise();
  enlarged_->activateWindow();
}

void MethodsPanel::setMechanism(const Preset& preset) {
  validate(preset);
  preset_ = preset;
}

void MethodsPanel::setHarnessSize(std::size_t samples, int repeats, bool include_fields) {
  if (samples < 10 || repeats < 1)
    throw std::invalid_argument("methods panel: expected samples >= 10 and repeats >= 1");
  samples_ = samples;
  repeats_ = repeats;
  include_fields_ = include_fields;
}

QString MethodsPanel::statusText() const { return status_->text(); }

void MethodsPanel::run() {
  if (task_.running()) return;
  run_button_->setEnabled(false);
  cancel_button_->setEnabled(true);
  status_->setText("Measuring " + mechanism_title(preset_) + "...");
  const Preset preset = preset_;
  const std::string compare = compare_->currentData().toString().toStdString();
  const std::size_t samples = samples_;
  const int repeats = repeats_;
  const bool fields = include_fields_;
  task_.start([this, preset, compare, samples, repeats, fields](const BackgroundTask::Run& run) {
    std::vector<methods::MethodRow> rows;
    QString message;
    bool completed = false;
    try {
      // Every device measures its own methods (core/mechanism.h).
      methods::HarnessOptions o;
      o.samples = samples;
      o.repeats = repeats;
      o.include_field = fields;
      o.field_resolutions = {16, 32};
      o.field_reference_resolution = 64;
      o.progress = [this, &run](double fraction, const std::string& stage) {
        const QString text = QString("%1 %: %2").arg(int(100 * fraction)).arg(QString::fromStdString(stage));
        run.progress([this, text] { status_->setText("Measuring: " + text); });
      };
      o.cancel = &run.cancelled;
      rows = make_mechanism(preset)->measure_methods(o);
      if (!compare.empty() && !run.cancelled.load()) {
        const std::vector<methods::MethodRow> second = make_mechanism(load_preset(compare))->measure_methods(o);
        rows.insert(rows.end(), second.begin(), second.end());
      }
      completed = !run.cancelled.load();
      message = completed ? QString("Measured %1 methods (%2 samples, median of %3 repeats).")
                                .arg(rows.size())
                                .arg(samples)
                                .arg(repeats)
                          : QString("Cancelled.");
    } catch (const std::exception& e) {
      message = QString("Failed: %1").arg(e.what());
    }
    run.finish([this, rows = std::move(rows), completed, message]() mutable {
      finish(std::move(rows), completed, message);
    });
  });
}

void MethodsPanel::cancel() {
  if (task_.cancel()) status_->setText("Cancelling...");
}

void MethodsPanel::finish(std::vector<methods::MethodRow> rows, bool completed, const QString& message) {
  run_button_->setEnabled(true);
  status_->setText(message);
  if (completed) {
    measured_title_ = mechanism_title(preset_);
    view_->setRows(rows);
    if (enlarged_) enlarged_->setRows(rows, measured_title_);
  }
  emit runFinished(completed);
}

}  // namespace linkscape::gui
