#include "gui/window/fit_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPainter>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSplitter>
#include <QVBoxLayout>
#include <algorithm>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "gui/figures/fit_report.h"
#include "gui/window/task_panel.h"

namespace linkscape::gui {

struct FitPanel::ParameterRow {
  std::string name;
  QCheckBox* free = nullptr;
  QDoubleSpinBox* lo = nullptr;
  QDoubleSpinBox* hi = nullptr;
};

namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }

// The chart of the panel's result, drawn into whatever rectangle it has.
class FitChart : public QWidget {
 public:
  explicit FitChart(const FitPanel* panel, QWidget* parent) : QWidget(parent), panel_(panel) {
    setMinimumSize(320, 220);
  }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    if (!panel_->result() || !panel_->problem()) {
      p.fillRect(rect(), Qt::white);
      p.setPen(QColor(110, 110, 110));
      p.drawText(rect(), Qt::AlignCenter | Qt::TextWordWrap,
                 panel_->showsSavedOutcome()
                     ? "The result above is the session's; Run again to chart every design evaluated."
                     : "Run sizes the device to the Task tab's task and criteria;\nevery design evaluated is charted here.");
      return;
    }
    draw_fit_chart(p, QRectF(rect()), *panel_->problem(), *panel_->result(),
                   make_mechanism(panel_->problem()->preset)->info());
  }

 private:
  const FitPanel* panel_;
};

// The task's text in the grammar of core/task.h (for the report).
std::string task_text(const task::TaskVolume& t) {
  std::string s = t.shape == task::Shape::Sphere
                      ? "sphere:diameter=" + format_number(t.diameter())
                      : "box:size=" + format_number(t.size.x()) + "," + format_number(t.size.y()) + "," +
                            format_number(t.size.z());
  if (t.centre)
    s += ",centre=" + format_number(t.centre->x()) + "," + format_number(t.centre->y()) + "," +
         format_number(t.centre->z());
  return s;
}

}  // namespace

FitPanel::FitPanel(const TaskPanel* task, QWidget* parent)
    : QWidget(parent), task_(task), worker_(this, [this] { cancel_button_->setEnabled(false); }) {
  auto* layout = new QVBoxLayout(this);
  setToolTip("Sizes the device to the Task tab's task and criteria. Free parameters vary within their bounds; "
             "the others keep the Design tab's values.");
  parameters_ = new QWidget(this);
  auto* grid = new QGridLayout(parameters_);
  grid->setContentsMargins(0, 0, 0, 0);
  grid->addWidget(new QLabel("free", parameters_), 0, 0);
  grid->addWidget(new QLabel("lower bound", parameters_), 0, 1);
  grid->addWidget(new QLabel("upper bound", parameters_), 0, 2);
  layout->addWidget(parameters_);

  auto* form = new QFormLayout;
  equal_edit_ = new QLineEdit(this);
  equal_edit_->setObjectName("fitEqual");
  equal_edit_->setPlaceholderText("e.g. L1,L2 (names separated by commas, groups by semicolons)");
  equal_edit_->setToolTip("Parameters held equal: one free variable per group, as --equal takes them (names "
                          "separated by commas; groups by semicolons, or one --equal each)");
  form->addRow("Hold equal", equal_edit_);
  connect(equal_edit_, &QLineEdit::editingFinished, this, &FitPanel::keepValidEqualGroups);  // for setting()
  mode_box_ = new QComboBox(this);
  mode_box_->setObjectName("fitMode");
  mode_box_->addItems({"Smallest size", "Largest ratio at size"});
  mode_box_->setToolTip("The smallest design meeting the task (every sample evaluated meets every criterion), or the "
                        "design of the given size whose task is furthest inside the criteria (the largest ratio)");
  size_box_ = new QDoubleSpinBox(this);
  size_box_->setObjectName("fitSize");
  size_box_->setRange(0, 1e6);
  size_box_->setDecimals(3);
  size_box_->setToolTip("The size held in the largest-ratio mode");
  auto* mode_row = new QHBoxLayout;
  mode_row->addWidget(mode_box_, 1);
  mode_row->addWidget(size_box_, 1);
  form->addRow("Mode", mode_row);
  centre_free_ = new QCheckBox("Place the task where it fits best", this);
  centre_free_->setToolTip("Else the task stays at the Task tab's centre");
  centre_free_->setObjectName("fitCentreFree");
  centre_free_->setChecked(true);
  form->addRow(centre_free_);
  region_edit_ = new QLineEdit(this);
  region_edit_->setObjectName("fitCentreRegion");
  region_edit_->setPlaceholderText("anywhere; or box:min=x,y,z,max=x,y,z or sphere:centre=x,y,z,radius=r");
  region_edit_->setToolTip("Where the task's centre may go when placed (the device's length unit); among equal "
                           "places the one nearest the home point");
  region_label_ = new QLabel("Centre within", this);
  form->addRow(region_label_, region_edit_);
  connect(centre_free_, &QCheckBox::toggled, region_edit_, &QWidget::setEnabled);
  layout->addLayout(form);

  auto* bar = new QHBoxLayout;
  run_button_ = new QPushButton("Run", this);
  run_button_->setObjectName("fitRun");
  cancel_button_ = new QPushButton("Cancel", this);
  cancel_button_->setObjectName("fitCancel");
  run_button_->setToolTip("Search the designs in the bounds (off the window's thread; the window stays usable)");
  cancel_button_->setToolTip("Stop the search; the designs evaluated so far are kept in the chart");
  cancel_button_->setEnabled(false);
  progress_ = new QProgressBar(this);
  progress_->setRange(0, 1);
  progress_->setValue(0);
  progress_->setTextVisible(false);
  bar->addWidget(run_button_);
  bar->addWidget(cancel_button_);
  bar->addWidget(progress_, 1);
  layout->addLayout(bar);
  status_ = new QLabel("Not run yet.", this);
  status_->setObjectName("fitStatus");
  status_->setWordWrap(true);
  layout->addWidget(status_);

  report_ = new QPlainTextEdit(this);
  report_->setObjectName("fitReport");
  report_->setReadOnly(true);
  report_->setLineWrapMode(QPlainTextEdit::WidgetWidth);
  report_->setMinimumHeight(80);
  chart_ = new FitChart(this, this);
  chart_->setObjectName("fitChart");
  auto* split = new QSplitter(Qt::Vertical, this);
  split->addWidget(report_);
  split->addWidget(chart_);
  split->setStretchFactor(0, 2);
  split->setStretchFactor(1, 3);
  layout->addWidget(split, 1);

  auto* actions = new QHBoxLayout;
  apply_button_ = new QPushButton("Apply design", this);
  apply_button_->setObjectName("fitApply");
  apply_button_->setToolTip("Set the Design tab's parameters to the chosen design");
  export_chart_button_ = new QPushButton("Export chart...", this);
  export_chart_button_->setObjectName("fitExportChart");
  export_csv_button_ = new QPushButton("Export CSV...", this);
  export_csv_button_->setObjectName("fitExportCsv");
  export_chart_button_->setToolTip("Save the chart of size against the worst measure as PNG, SVG or PDF");
  export_csv_button_->setToolTip("Save every design evaluated, with its verdict and margins, as CSV (as linkscape fit -o)");
  for (QPushButton* b : {apply_button_, export_chart_button_, export_csv_button_}) {
    b->setEnabled(false);
    actions->addWidget(b);
  }
  layout->addLayout(actions);

  connect(mode_box_, &QComboBox::currentIndexChanged, this, [this] { syncMode(); });
  connect(run_button_, &QPushButton::clicked, this, &FitPanel::run);
  connect(cancel_button_, &QPushButton::clicked, this, &FitPanel::cancel);
  connect(apply_button_, &QPushButton::clicked, this, &FitPanel::applyDesign);
  auto export_to = [this](const QString& filter, const std::function<void(const std::filesystem::path&)>& write) {
    const QString path = QFileDialog::getSaveFileName(this, "Export", QString(), filter);
    if (path.isEmpty()) return;
    try {
      write(path.toStdString());
    } catch (const std::exception& e) {
      QMessageBox::warning(this, "Export failed", e.what());
    }
  };
  connect(export_chart_button_, &QPushButton::clicked, this, [this, export_to] {
    export_to("Chart (*.png *.svg *.pdf)", [this](const std::filesystem::path& p) { exportChart(p); });
  });
  connect(export_csv_button_, &QPushButton::clicked, this, [this, export_to] {
    export_to("CSV (*.csv)", [this](const std::filesystem::path& p) { exportCsv(p); });
  });
  syncMode();
}

FitPanel::~FitPanel() = default;  // the worker cancels and joins a search in flight

void FitPanel::syncMode() { size_box_->setEnabled(mode_box_->currentIndex() == 1); }

void FitPanel::setDevice(const Preset& preset, const Eigen::VectorXd& pose) {
  preset_ = preset;
  pose_ = pose;
  if (!rows_.empty()) return;
  const std::shared_ptr<const Mechanism> m = make_mechanism(preset);
  const MechanismInfo& info = m->info();
  const std::vector<std::string> sized = fit::size_terms(info);
  auto* grid = static_cast<QGridLayout*>(parameters_->layout());
  for (const Quantity& q : info.parameters) {
    if (!q.in_panel) continue;
    ParameterRow row;
    row.name = q.name;
    const int r = grid->rowCount();
    row.free = new QCheckBox(qs(q.name + (q.unit.empty() ? "" : " (" + q.unit + ")")), parameters_);
    row.free->setObjectName(qs("fitFree_" + q.name));
    row.free->setToolTip(qs(q.description));
    row.free->setChecked(std::find(sized.begin(), sized.end(), q.name) != sized.end());
    grid->addWidget(row.free, r, 0);
    for (auto [box, value, suffix] : {std::tuple{&row.lo, q.range.lo, "Lo"}, std::tuple{&row.hi, q.range.hi, "Hi"}}) {
      *box = new QDoubleSpinBox(parameters_);
      (*box)->setObjectName(qs("fit" + std::string(suffix) + "_" + q.name));
      (*box)->setDecimals(3);
      (*box)->setRange(-1e4, 1e4);
      (*box)->setValue(value);
      if (!q.unit.empty()) (*box)->setSuffix(qs(" " + q.unit));
      (*box)->setToolTip(qs((suffix[0] == 'L' ? "Lower" : "Upper") + std::string(" bound of ") + q.name +
                            " in the search (default: its range in the Design tab)"));
      grid->addWidget(*box, r, suffix[0] == 'L' ? 1 : 2);
    }
    rows_.push_back(row);
  }
  size_box_->setSuffix(qs(" " + info.length_unit));
  region_label_->setText(qs("Centre within (" + info.length_unit + ")"));
  size_box_->setToolTip(qs("The size held in the largest-ratio mode: " + info.size_description));
  size_box_->setValue(m->size());
}

void FitPanel::setFree(const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (std::none_of(rows_.begin(), rows_.end(), [&](const ParameterRow& r) { return r.name == n; }))
      throw std::invalid_argument("fit panel: no design parameter '" + n + "'");
  for (ParameterRow& r : rows_) r.free->setChecked(std::find(names.begin(), names.end(), r.name) != names.end());
}

void FitPanel::setBounds(const std::string& name, double lo, double hi) {
  for (ParameterRow& r : rows_)
    if (r.name == name) {
      r.lo->setValue(lo);
      r.hi->setValue(hi);
      return;
    }
  throw std::invalid_argument("fit panel: no design parameter '" + name + "'");
}

void FitPanel::setEqual(const std::string& groups) { equal_edit_->setText(qs(groups)); }

void FitPanel::setMode(Mode mode, double size) {
  mode_box_->setCurrentIndex(mode == Mode::SmallestSize ? 0 : 1);
  if (mode == Mode::LargestMarginAtSize) size_box_->setValue(size);
}

void FitPanel::setCentreFree(bool free) { centre_free_->setChecked(free); }

void FitPanel::setCentreRegion(const std::string& region) {
  if (!region.empty()) task::parse_centre_region(region);  // throws for bad text, nothing changed
  region_edit_->setText(qs(region));
}

std::string FitPanel::centreRegion() const { return region_edit_->text().trimmed().toStdString(); }

FitSetting FitPanel::setting() const {
  FitSetting s;
  for (const ParameterRow& r : rows_) {
    if (r.free->isChecked()) s.free.push_back(r.name);
    if (r.lo->value() < r.hi->value()) s.bounds[r.name] = {r.lo->value(), r.hi->value()};
  }
  keepValidEqualGroups();
  s.equal = last_valid_equal_;
  s.largest_margin = mode_box_->currentIndex() == 1;
  s.size = size_box_->value();
  s.centre_free = centre_free_->isChecked();
  try {  // the region's text as typed, where it reads; else the last that did
    const std::string region = centreRegion();
    if (!region.empty()) task::parse_centre_region(region);
    last_valid_region_ = region;
  } catch (const std::invalid_argument&) {
  }
  s.centre_region = last_valid_region_;
  return s;
}

void FitPanel::keepValidEqualGroups() const {
  const std::string equal = equal_edit_->text().toStdString();
  bool known = true;  // every name in the groups is a design parameter
  std::string name;
  for (const char c : equal + ";") {
    if (c == ';' || c == ',') {
      known = known && (name.empty() || std::any_of(rows_.begin(), rows_.end(),
                                                    [&](const ParameterRow& r) { return r.name == name; }));
      name.clear();
    } else if (c != ' ') {
      name += c;
    }
  }
  if (known) last_valid_equal_ = equal;
}

void FitPanel::applySetting(const FitSetting& s) {
  if (!s.centre_region.empty()) task::parse_centre_region(s.centre_region);  // throws before anything changes
  for (const auto& [name, range] : s.bounds)  // checked before anything changes (setFree checks its own)
    if (std::none_of(rows_.begin(), rows_.end(), [&name = name](const ParameterRow& r) { return r.name == name; }))
      throw std::invalid_argument("fit panel: no design parameter '" + name + "'");
  setFree(s.free);
  for (const auto& [name, range] : s.bounds) setBounds(name, range[0], range[1]);
  setEqual(s.equal);
  last_valid_equal_ = s.equal;
  setMode(s.largest_margin ? Mode::LargestMarginAtSize : Mode::SmallestSize, s.size);
  setCentreFree(s.centre_free);
  setCentreRegion(s.centre_region);
  last_valid_region_ = s.centre_region;
}

std::optional<FitOutcome> FitPanel::outcome() const {
  if (!result_ || !problem_) return saved_;
  return FitOutcome{reportText().toStdString(), statusText().toStdString(), chosenDesign(), chosenCentre()};
}

void FitPanel::applyOutcome(const FitOutcome& outcome) {
  if (worker_.running()) return;  // the run's result is the newer
  result_.reset();
  problem_.reset();
  saved_ = outcome;
  report_->setPlainText(qs(outcome.report));
  status_->setText(qs(outcome.status));
  apply_button_->setEnabled(!outcome.design.empty());
  export_chart_button_->setEnabled(false);
  export_csv_button_->setEnabled(false);
  chart_->update();
}

void FitPanel::setSearchSettings(const task::InscribedOptions& inscribed, int task_resolution, double tolerance) {
  inscribed_ = inscribed;
  task_resolution_ = task_resolution;
  tolerance_ = tolerance;
}

fit::Problem FitPanel::makeProblem() const {
  if (rows_.empty()) throw std::invalid_argument("fit: no device");
  fit::Problem p;
  p.preset = preset_;
  p.pose = pose_;
  p.task = task_->volume();
  if (centre_free_->isChecked()) {
    p.task.centre.reset();
    const std::string region = region_edit_->text().trimmed().toStdString();
    if (!region.empty()) p.inscribed.centres = task::parse_centre_region(region);
  }
  p.task.text = task_text(p.task);
  p.criteria = task_->criteria();
  std::vector<std::string> free, equal;
  for (const ParameterRow& r : rows_)
    if (r.free->isChecked()) free.push_back(r.name);
  std::stringstream groups(equal_edit_->text().toStdString());
  for (std::string g; std::getline(groups, g, ';');) {
    g.erase(std::remove(g.begin(), g.end(), ' '), g.end());
    if (g.empty()) continue;
    equal.push_back(g);
    std::stringstream names(g);  // a group's parameters are free
    for (std::string n; std::getline(names, n, ',');)
      if (std::find(free.begin(), free.end(), n) == free.end()) free.push_back(n);
  }
  if (free.empty()) throw std::invalid_argument("fit: tick at least one free parameter");
  p.variables = fit::variables(*make_mechanism(preset_), free, equal, {});
  // A group's bounds: the intersection of its parameters' rows.
  for (fit::Variable& v : p.variables) {
    v.lo = -std::numeric_limits<double>::infinity();
    v.hi = std::numeric_limits<double>::infinity();
    for (const ParameterRow& r : rows_)
      if (std::count(v.parameters.begin(), v.parameters.end(), r.name)) {
        v.lo = std::max(v.lo, r.lo->value());
        v.hi = std::min(v.hi, r.hi->value());
      }
  }
  p.inscribed.resolution = inscribed_.resolution;
  p.inscribed.refinements = inscribed_.refinements;
  p.inscribed.places = inscribed_.places;
  p.task_resolution = task_resolution_;
  p.tolerance = tolerance_;
  if (mode_box_->currentIndex() == 1) p.size = size_box_->value();
  return p;
}

void FitPanel::run() {
  if (worker_.running()) return;
  fit::Problem problem;
  try {
    problem = makeProblem();
  } catch (const std::invalid_argument& e) {
    status_->setText(QString("Cannot run: %1").arg(e.what()));
    emit runFinished(false);
    return;
  }
  run_button_->setEnabled(false);
  cancel_button_->setEnabled(true);
  progress_->setRange(0, 0);  // busy: the number of designs is not known in advance
  status_->setText("Searching...");
  auto shared = std::make_shared<const fit::Problem>(std::move(problem));
  worker_.start([this, shared](const BackgroundTask::Run& run) {
    std::optional<fit::Result> result;
    QString message;
    fit::Progress progress;
    progress.cancel = &run.cancelled;
    std::optional<double> best;
    const bool at_size = shared->size.has_value();
    progress.design = [&](const fit::Row& row, std::size_t n) {
      if (at_size ? row.invalid.empty() && (!best || row.ratio > *best) : row.meets && (!best || row.size < *best))
        best = at_size ? row.ratio : row.size;
      QString text = QString("%1 designs evaluated").arg(n);
      if (best) text += QString(at_size ? ", largest ratio so far %1" : ", smallest meeting size so far %1").arg(*best, 0, 'g', 4);
      run.progress([this, text] { status_->setText(text); });
    };
    try {
      fit::Result r = fit::solve(*shared, progress);
      if (run.cancelled.load()) message = "Cancelled.";
      else result = std::move(r);
    } catch (const std::exception& e) {
      message = QString("Cannot run: %1").arg(e.what());
    }
    run.finish([this, shared, result = std::move(result), message]() mutable {
      if (result) problem_ = *shared;
      finish(std::move(result), message);
    });
  });
}

void FitPanel::cancel() {
  if (worker_.cancel()) status_->setText("Cancelling...");
}

void FitPanel::finish(std::optional<fit::Result> result, const QString& message) {
  run_button_->setEnabled(true);
  progress_->setRange(0, 1);
  progress_->setValue(result ? 1 : 0);
  const bool completed = result.has_value();
  if (completed) {
    saved_.reset();
    result_ = std::move(result);
    const std::string report = fit_report(*problem_, *result_, make_mechanism(problem_->preset)->info());
    report_->setPlainText(qs(report));
    // The lines with the answer and its verdict: the third and fourth of the report.
    QStringList lines = qs(report).split('\n');
    QString status = lines.size() > 3 ? lines[2] + "\n" + lines[3].trimmed() : lines.value(0);
    const std::optional<std::size_t> chosen = result_->best ? result_->best : result_->closest;
    if (chosen) {  // where the task sits for that design, from its home point
      const fit::Row& row = result_->rows[*chosen];
      status += "\n" + centre_from_home_text(row.centre, row.home, row.size,
                                             qs(make_mechanism(problem_->preset)->info().length_unit));
    }
    status_->setText(status);
    apply_button_->setEnabled(chosen.has_value());
    export_chart_button_->setEnabled(true);
    export_csv_button_->setEnabled(true);
    chart_->update();
  } else {
    status_->setText(message);
  }
  emit runFinished(completed);
}

std::map<std::string, double> FitPanel::chosenDesign() const {
  if (!result_ || !problem_) return saved_ ? saved_->design : std::map<std::string, double>{};
  const std::optional<std::size_t> chosen = result_->best ? result_->best : result_->closest;
  if (!chosen) return {};
  std::map<std::string, double> out;
  for (const fit::Variable& v : problem_->variables)
    for (const std::string& name : v.parameters) out[name] = result_->rows[*chosen].parameters.at(name);
  return out;
}

std::optional<Eigen::Vector3d> FitPanel::chosenCentre() const {
  if (!result_ || !problem_) return saved_ ? saved_->centre : std::nullopt;
  if (problem_->task.centre) return std::nullopt;
  const std::optional<std::size_t> chosen = result_->best ? result_->best : result_->closest;
  if (!chosen) return std::nullopt;
  return result_->rows[*chosen].centre;
}

void FitPanel::applyDesign() {
  const std::map<std::string, double> design = chosenDesign();
  if (!design.empty()) emit applyRequested(design);
}

QString FitPanel::statusText() const { return status_->text(); }
QString FitPanel::reportText() const { return report_->toPlainText(); }

void FitPanel::exportChart(const std::filesystem::path& path) const {
  if (!result_ || !problem_) throw std::invalid_argument("fit: nothing to export before a run");
  write_fit_chart(path, *problem_, *result_, make_mechanism(problem_->preset)->info());
}

void FitPanel::exportCsv(const std::filesystem::path& path) const {
  if (!result_ || !problem_) throw std::invalid_argument("fit: nothing to export before a run");
  if (path.extension() != ".csv") throw std::invalid_argument("fit: the CSV must end in .csv, got '" + path.string() + "'");
  write_fit_csv(path, *problem_, *result_, make_mechanism(problem_->preset)->info());
}

}  // namespace linkscape::gui
