#include "gui/methods_panel.h"

#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPainter>
#include <QPushButton>
#include <QSplitter>
#include <QTableWidget>
#include <QVBoxLayout>

#include <exception>
#include <stdexcept>

#include "core/mechanism.h"
#include "gui/method_chart.h"

namespace linkscape::gui {
namespace {

// The chart, drawn into whatever rectangle the widget has.
class ChartView : public QWidget {
 public:
  ChartView(const std::vector<methods::MethodRow>& rows, const QString& title, QWidget* parent)
      : QWidget(parent), rows_(rows), title_(title) {
    setMinimumSize(320, 240);
  }
  void set_title(const QString& t) { title_ = t; }
  const QString& title() const { return title_; }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    if (rows_.empty()) {
      p.fillRect(rect(), Qt::white);
      p.setPen(QColor(110, 110, 110));
      p.drawText(rect(), Qt::AlignCenter, "Run measures every method's time and error.");
      return;
    }
    draw_method_chart(p, QRectF(rect()), rows_, title_);
  }

 private:
  const std::vector<methods::MethodRow>& rows_;
  QString title_;
};

QString mechanism_title(const Preset& preset) {
  return QString::fromStdString(preset.title.empty() ? preset.mechanism : preset.title);
}

}  // namespace

MethodsPanel::MethodsPanel(QWidget* parent) : QWidget(parent) {
  preset_ = load_preset(default_mechanism());
  auto* layout = new QVBoxLayout(this);
  auto* bar = new QHBoxLayout;
  run_button_ = new QPushButton("Run", this);
  run_button_->setObjectName("run");
  run_button_->setToolTip("Measure time per evaluation and error of every method for the current parameters");
  cancel_button_ = new QPushButton("Cancel", this);
  cancel_button_->setObjectName("cancel");
  cancel_button_->setEnabled(false);
  status_ = new QLabel("Not measured yet.", this);
  status_->setObjectName("status");
  // The chart has a panel per mechanism and family: a dock is too small to
  // read it, so it also opens in a window of its own (kept current).
  auto* enlarge = new QPushButton("Enlarge", this);
  enlarge->setObjectName("enlarge");
  enlarge->setToolTip("Open the chart in its own window, large enough to read");
  bar->addWidget(run_button_);
  bar->addWidget(cancel_button_);
  bar->addWidget(enlarge);
  bar->addWidget(status_, 1);
  layout->addLayout(bar);
  auto* split = new QSplitter(Qt::Vertical, this);
  chart_ = new ChartView(rows_, "", split);
  chart_->setObjectName("chart");
  table_ = new QTableWidget(0, 8, split);
  table_->setObjectName("table");
  table_->setHorizontalHeaderLabels(
      {"family", "method", "parameter", "time / eval", "median error", "p99", "max", "not ok"});
  table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  split->addWidget(chart_);
  split->addWidget(table_);
  split->setStretchFactor(0, 3);
  split->setStretchFactor(1, 1);
  layout->addWidget(split, 1);
  connect(enlarge, &QPushButton::clicked, this, [this] {
    auto* big = new ChartView(rows_, static_cast<ChartView*>(chart_)->title(), this);
    big->setWindowFlags(Qt::Window);
    big->setAttribute(Qt::WA_DeleteOnClose);
    big->setWindowTitle("Linkscape: speed against accuracy");
    big->resize(1400, 1000);
    connect(this, &MethodsPanel::runFinished, big, [this, big] {
      big->set_title(static_cast<ChartView*>(chart_)->title());
      big->update();
    });
    big->show();
  });
  connect(run_button_, &QPushButton::clicked, this, &MethodsPanel::run);
  connect(cancel_button_, &QPushButton::clicked, this, &MethodsPanel::cancel);
}

MethodsPanel::~MethodsPanel() {
  if (cancel_) cancel_->store(true);
  join_worker();
}

void MethodsPanel::join_worker() {
  if (worker_.joinable()) worker_.join();
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
  if (running_) return;
  join_worker();  // a finished worker may still be unwinding
  running_ = true;
  const unsigned generation = ++generation_;
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  run_button_->setEnabled(false);
  cancel_button_->setEnabled(true);
  status_->setText("Measuring " + mechanism_title(preset_) + "...");
  const Preset preset = preset_;
  const std::size_t samples = samples_;
  const int repeats = repeats_;
  const bool fields = include_fields_;
  const auto cancel = cancel_;
  // Results come back through queued calls with this object as context: Qt
  // drops them if the panel is gone, and the destructor joins the thread.
  auto report = [this, generation](double fraction, const std::string& stage) {
    const QString text = QString("%1 %: %2").arg(int(100 * fraction)).arg(QString::fromStdString(stage));
    QMetaObject::invokeMethod(
        this,
        [this, generation, text] {
          if (generation == generation_ && running_) status_->setText("Measuring: " + text);
        },
        Qt::QueuedConnection);
  };
  worker_ = std::thread([this, generation, preset, samples, repeats, fields, cancel, report] {
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
      o.progress = report;
      o.cancel = cancel.get();
      rows = make_mechanism(preset)->measure_methods(o);
      completed = !cancel->load();
      message = completed ? QString("Measured %1 methods (%2 samples, median of %3 repeats).")
                                .arg(rows.size())
                                .arg(samples)
                                .arg(repeats)
                          : QString("Cancelled.");
    } catch (const std::exception& e) {
      message = QString("Failed: %1").arg(e.what());
    }
    QMetaObject::invokeMethod(
        this,
        [this, generation, rows = std::move(rows), completed, message]() mutable {
          finish(generation, std::move(rows), completed, message);
        },
        Qt::QueuedConnection);
  });
}

void MethodsPanel::cancel() {
  if (!running_ || !cancel_) return;
  cancel_->store(true);
  status_->setText("Cancelling...");
}

void MethodsPanel::finish(unsigned generation, std::vector<methods::MethodRow> rows, bool completed,
                          const QString& message) {
  if (generation != generation_) return;
  running_ = false;
  join_worker();
  run_button_->setEnabled(true);
  cancel_button_->setEnabled(false);
  status_->setText(message);
  if (completed) {
    rows_ = std::move(rows);
    static_cast<ChartView*>(chart_)->set_title("Speed against accuracy: " + mechanism_title(preset_));
    fill_table();
    chart_->update();
  }
  emit runFinished(completed);
}

void MethodsPanel::fill_table() {
  table_->setRowCount(int(rows_.size()));
  auto number = [](double v) { return QString::number(v, 'g', 3); };
  for (int i = 0; i < int(rows_.size()); ++i) {
    const methods::MethodRow& r = rows_[std::size_t(i)];
    const QString cells[] = {QString::fromStdString(r.family),
                             QString::fromStdString(r.method),
                             QString::fromStdString(r.parameter),
                             number(r.seconds_per_evaluation) + " s",
                             number(r.error_median) + " " + QString::fromStdString(r.error_unit),
                             number(r.error_p99),
                             number(r.error_max),
                             QString::number(r.failures)};
    for (int c = 0; c < 8; ++c) table_->setItem(i, c, new QTableWidgetItem(cells[c]));
  }
}

}  // namespace linkscape::gui
