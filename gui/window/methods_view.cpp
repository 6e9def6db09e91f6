#include "gui/window/methods_view.h"

#include <QChart>
#include <QChartView>
#include <QComboBox>
#include <QCursor>
#include <QGuiApplication>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLegend>
#include <QLineSeries>
#include <QCategoryAxis>
#include <QMouseEvent>
#include <QPushButton>
#include <QScatterSeries>
#include <QScreen>
#include <QShortcut>
#include <QSplitter>
#include <QTableWidget>
#include <QToolTip>
#include <QVBoxLayout>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>

#include "gui/figures/method_chart.h"

namespace linkscape::gui {
namespace {

using methods::MethodRow;

bool plotted(const MethodRow& r) {
  return std::isfinite(r.seconds_per_evaluation) && r.seconds_per_evaluation > 0 && std::isfinite(r.error_median);
}
double drawn_error(const MethodRow& r) { return std::max(r.error_median, kExactErrorFloor); }

QString number(double v) { return QString::number(v, 'g', 3); }

QString seconds_text(double s) {
  if (!std::isfinite(s) || s <= 0) return number(s) + " s";
  static const std::pair<double, const char*> units[] = {{1, "s"}, {1e-3, "ms"}, {1e-6, "µs"}, {1e-9, "ns"}};
  for (const auto& [scale, unit] : units)
    if (s >= scale) return number(s / scale) + " " + unit;
  return number(s) + " s";
}

// Qt Charts' log axis loses ranges narrower than about 1e-12 (every error
// of a good method), so the chart plots log10 of time and error on linear
// axes and labels whole decades itself.
QPointF chart_point(const MethodRow& r) {
  return {std::log10(r.seconds_per_evaluation), std::log10(drawn_error(r))};
}

// A linear axis of log10 values, labelled with the values themselves: every
// `step` decades, or at 1, 2 and 5 of each decade when there is room.
class DecadeAxis : public QCategoryAxis {
 public:
  DecadeAxis(const QString& title, double lo, double hi, std::function<QString(double)> label)
      : label_(std::move(label)) {
    setTitleText(title);
    setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
    setRange(std::floor(lo - 0.15), std::ceil(hi + 0.15));
    QFont font = titleFont();
    font.setBold(false);
    setTitleFont(font);
  }

  // Labels that leave `pixels` each over `length` pixels.
  void fit(double length, double pixels) {
    if (length <= 0) return;
    const double lo = min(), hi = max();
    const int room = std::max(1, int(length / pixels));
    const int step = std::max(1, int(std::ceil((hi - lo) / room)));
    const bool fine = 3 * (hi - lo) <= room;
    std::vector<double> at;
    for (int k = int(std::floor(lo)); k <= int(std::ceil(hi)); ++k) {
      if (k % step != 0) continue;
      for (double m : {1.0, 2.0, 5.0}) {
        const double x = k + std::log10(m);
        if (x >= lo - 1e-9 && x <= hi + 1e-9 && (m == 1.0 || fine)) at.push_back(x);
      }
    }
    QStringList labels;
    for (double x : at) labels << label_(x);
    if (labels == categoriesLabels()) return;
    for (const QString& old : categoriesLabels()) remove(old);
    setStartValue(lo);
    for (std::size_t i = 0; i < at.size(); ++i) append(labels[int(i)], at[i]);
    setRange(lo, hi);
  }

 private:
  std::function<QString(double)> label_;
};

QString time_at(double x) { return seconds_text(std::pow(10.0, x)); }

QString error_at(double x) {
  const int k = int(std::floor(x + 1e-9));
  const long mantissa = std::lround(std::pow(10.0, x - k));
  return mantissa == 1 ? decade_label(k) : QString("%1·%2").arg(mantissa).arg(decade_label(k));
}

// A number in a table cell that sorts numerically (NaN after every number).
class NumberItem : public QTableWidgetItem {
 public:
  NumberItem(double value, const QString& text) : QTableWidgetItem(text) {
    setData(Qt::UserRole, value);
    setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
  }
  bool operator<(const QTableWidgetItem& other) const override {
    const double a = data(Qt::UserRole).toDouble(), b = other.data(Qt::UserRole).toDouble();
    if (std::isnan(a) || std::isnan(b)) return !std::isnan(a) && std::isnan(b);
    return a < b;
  }
};

// Double-click zooms out to everything.
class ChartView : public QChartView {
 public:
  ChartView(QChart* chart, MethodsView* owner) : QChartView(chart, owner), owner_(owner) {}

 protected:
  void mouseDoubleClickEvent(QMouseEvent* event) override {
    owner_->resetZoom();
    event->accept();
  }

 private:
  MethodsView* owner_;
};

const QStringList kColumns = {"family",    "method",    "parameter", "time / eval (s)", "median error",
                              "p99 error", "max error", "unit",      "samples",         "not ok"};

}  // namespace

MethodsView::MethodsView(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  auto* bar = new QHBoxLayout;
  family_ = new QComboBox(this);
  family_->setObjectName("family");
  family_->setToolTip("The family of methods the chart shows");
  family_->setSizeAdjustPolicy(QComboBox::AdjustToMinimumContentsLengthWithIcon);
  family_->setMinimumContentsLength(12);
  auto* reset = new QPushButton("Reset zoom", this);
  reset->setObjectName("resetZoom");
  reset->setToolTip("Show every point again (or double-click the chart)");
  bar->addWidget(family_, 1);
  bar->addWidget(reset);
  layout->addLayout(bar);

  auto* chart = new QChart;
  chart->setBackgroundRoundness(0);
  // Room on the right for half of the last time label, centred on its tick.
  chart->setMargins(QMargins(2, 2, 2 + QFontMetrics(font()).horizontalAdvance("100 ms") / 2, 2));
  // Qt Charts' legend is one line that elides long method names at panel
  // width: a wrapped label under the chart instead.
  chart->legend()->hide();
  view_ = new ChartView(chart, this);
  view_->setObjectName("chart");
  view_->setRenderHint(QPainter::Antialiasing);
  view_->setRubberBand(QChartView::RectangleRubberBand);
  view_->setMinimumSize(260, 200);
  legend_ = new QLabel(this);
  legend_->setObjectName("legend");
  legend_->setWordWrap(true);
  legend_->setTextFormat(Qt::RichText);
  note_ = new QLabel(this);
  note_->setObjectName("chartNote");
  note_->setWordWrap(true);
  note_->setForegroundRole(QPalette::PlaceholderText);
  auto* chart_box = new QWidget(this);
  auto* chart_layout = new QVBoxLayout(chart_box);
  chart_layout->setContentsMargins(0, 0, 0, 0);
  chart_layout->setSpacing(2);
  chart_layout->addWidget(view_, 1);
  chart_layout->addWidget(legend_);
  chart_layout->addWidget(note_);

  table_ = new QTableWidget(0, int(kColumns.size()), this);
  table_->setObjectName("table");
  table_->setHorizontalHeaderLabels(kColumns);
  table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  table_->horizontalHeader()->setToolTip("Click a column to sort by it");
  table_->verticalHeader()->setVisible(false);
  table_->verticalHeader()->setDefaultSectionSize(fontMetrics().height() + 6);  // more rows in a short dock
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setMinimumHeight(90);
  table_->horizontalHeader()->setSortIndicator(-1, Qt::AscendingOrder);  // the harness' order until a click

  auto* split = new QSplitter(Qt::Vertical, this);  // below, not beside: every column in view
  split->setObjectName("chartTableSplit");
  split->setChildrenCollapsible(false);
  split->addWidget(chart_box);
  split->addWidget(table_);
  split->setStretchFactor(0, 3);
  split->setStretchFactor(1, 2);
  layout->addWidget(split, 1);

  connect(family_, &QComboBox::currentIndexChanged, this, [this] { show_family(); });
  connect(reset, &QPushButton::clicked, this, &MethodsView::resetZoom);
  connect(chart, &QChart::plotAreaChanged, this, [this] { fit_ticks(); });
  show_family();
}

QChart* MethodsView::chart() const { return view_->chart(); }
QString MethodsView::note() const { return note_->text(); }

void MethodsView::setRows(const std::vector<MethodRow>& rows) {
  rows_ = rows;
  const QString keep = family();
  QStringList names;
  std::vector<std::string> units;  // of each family's first row
  for (const auto& r : rows_)
    if (!names.contains(QString::fromStdString(r.family))) {
      names << QString::fromStdString(r.family);
      units.push_back(r.error_unit);
    }
  const QSignalBlocker block(family_);
  family_->clear();
  for (int k = 0; k < names.size(); ++k)
    family_->addItem(method_family_title(names[k].toStdString(), units[std::size_t(k)]), names[k]);
  family_->setCurrentIndex(std::max(0, int(names.indexOf(keep))));
  family_->setEnabled(!names.isEmpty());
  show_family();
  fill_table();
}

QStringList MethodsView::families() const {
  QStringList out;
  for (int i = 0; i < family_->count(); ++i) out << family_->itemData(i).toString();
  return out;
}

QString MethodsView::family() const { return family_->currentData().toString(); }

void MethodsView::setFamily(const QString& family) {
  const int i = family_->findData(family);
  if (i >= 0) family_->setCurrentIndex(i);
}

void MethodsView::show_family() {
  QChart* chart = view_->chart();
  chart->removeAllSeries();
  for (QAbstractAxis* axis : chart->axes()) {
    chart->removeAxis(axis);
    delete axis;
  }
  const std::string fam = family().toStdString();
  std::vector<std::size_t> shown;
  int unplotted = 0, exact = 0;
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    if (rows_[i].family != fam) continue;
    if (!plotted(rows_[i])) ++unplotted;
    else {
      shown.push_back(i);
      exact += rows_[i].error_median <= 0;
    }
  }
  QStringList notes;
  legend_->clear();
  if (rows_.empty()) chart->setTitle("Run measures every method's time and error.");
  else chart->setTitle({});
  if (!shown.empty()) {
    QPointF lo = chart_point(rows_[shown.front()]), hi = lo;
    for (std::size_t i : shown) {
      const QPointF p = chart_point(rows_[i]);
      lo = {std::min(lo.x(), p.x()), std::min(lo.y(), p.y())};
      hi = {std::max(hi.x(), p.x()), std::max(hi.y(), p.y())};
    }
    const bool field = fam == "field";
    auto* x = new DecadeAxis(field ? "time per field" : "time per evaluation", lo.x(), hi.x(), time_at);
    auto* y = new DecadeAxis(method_error_label(fam, rows_[shown.front()].error_unit), lo.y(), hi.y(), error_at);
    chart->addAxis(x, Qt::AlignBottom);
    chart->addAxis(y, Qt::AlignLeft);
    connect(x, &QValueAxis::rangeChanged, this, [this] { fit_ticks(); });
    connect(y, &QValueAxis::rangeChanged, this, [this] { fit_ticks(); });

    // The Pareto front underneath the markers, as a staircase to the right edge.
    const std::vector<std::size_t> front = methods::pareto_front(rows_, fam);
    auto* stairs = new QLineSeries;
    stairs->setName("Pareto front");
    stairs->setPen(QPen(QColor(60, 60, 60), 1.5, Qt::DashLine));
    for (std::size_t k = 0; k < front.size(); ++k) {
      const MethodRow& r = rows_[front[k]];
      if (!plotted(r)) continue;
      const QPointF p = chart_point(r);
      if (stairs->count() > 0) stairs->append(p.x(), stairs->at(stairs->count() - 1).y());
      stairs->append(p);
    }
    if (stairs->count() > 0) stairs->append(x->max(), stairs->at(stairs->count() - 1).y());
    chart->addSeries(stairs);
    stairs->attachAxis(x);
    stairs->attachAxis(y);

    // One series per method, in table order.
    static const std::pair<QScatterSeries::MarkerShape, const char*> shapes[] = {
        {QScatterSeries::MarkerShapeCircle, "●"},          {QScatterSeries::MarkerShapeRectangle, "■"},
        {QScatterSeries::MarkerShapeTriangle, "▲"},        {QScatterSeries::MarkerShapeRotatedRectangle, "◆"},
        {QScatterSeries::MarkerShapePentagon, "⬟"},        {QScatterSeries::MarkerShapeStar, "★"}};
    QStringList entries;
    std::vector<QScatterSeries*> series;
    for (std::size_t i : shown) {
      const QString name = QString::fromStdString(rows_[i].method);
      auto it = std::find_if(series.begin(), series.end(), [&](QScatterSeries* s) { return s->name() == name; });
      if (it == series.end()) {
        const int k = int(series.size());
        auto* s = new QScatterSeries;
        s->setName(name);
        s->setMarkerShape(shapes[k % 6].first);
        // Non-breaking hyphens: an entry wraps as a whole ("complex-step").
        entries << QString("<span style=\"color:%1\">%2</span>&nbsp;%3")
                       .arg(method_colour(k).name(), shapes[k % 6].second,
                            name.toHtmlEscaped().replace('-', QChar(0x2011)));
        s->setMarkerSize(11);
        s->setColor(method_colour(k));
        s->setBorderColor(method_colour(k).darker(140));
        chart->addSeries(s);
        s->attachAxis(x);
        s->attachAxis(y);
        connect(s, &QScatterSeries::hovered, this,
                [this, name](const QPointF& p, bool entered) { on_hover(name, p, entered); });
        series.push_back(s);
        it = series.end() - 1;
      }
      (*it)->append(chart_point(rows_[i]));
    }
    legend_->setText(entries.join("&nbsp;&nbsp; "));
    if (exact > 0)
      notes << QString("%1 exact result%2 (error 0) drawn at %3.")
                   .arg(exact)
                   .arg(exact > 1 ? "s" : "")
                   .arg(number(kExactErrorFloor));
    notes << "Dashed: the Pareto front. Drag to zoom; double-click to see all.";
  }
  if (unplotted > 0)
    notes << QString("%1 row%2 with a non-finite value or a zero time: only in the table.")
                 .arg(unplotted)
                 .arg(unplotted > 1 ? "s" : "");
  note_->setText(notes.join(' '));
  note_->setVisible(!notes.isEmpty());
  legend_->setVisible(!legend_->text().isEmpty());
  fit_ticks();
}

void MethodsView::fit_ticks() {
  const QRectF area = view_->chart()->plotArea();
  for (QAbstractAxis* axis : view_->chart()->axes(Qt::Horizontal))
    if (auto* decades = dynamic_cast<DecadeAxis*>(axis)) decades->fit(area.width(), 64);
  for (QAbstractAxis* axis : view_->chart()->axes(Qt::Vertical))
    if (auto* decades = dynamic_cast<DecadeAxis*>(axis)) decades->fit(area.height(), 26);
}

void MethodsView::resetZoom() {
  view_->chart()->zoomReset();
  show_family();
}

QString MethodsView::pointTip(const QString& method, const QPointF& point) const {
  // The family's row of `method` charted nearest to `point`.
  const MethodRow* best = nullptr;
  double best_distance = std::numeric_limits<double>::infinity();
  const std::string fam = family().toStdString();
  for (const auto& r : rows_) {
    if (r.family != fam || QString::fromStdString(r.method) != method || !plotted(r)) continue;
    const QPointF at = chart_point(r);
    const double d = std::hypot(at.x() - point.x(), at.y() - point.y());
    if (d < best_distance) best_distance = d, best = &r;
  }
  if (!best) return {};
  const QString unit = best->error_unit == "rad" ? " rad" : "";
  QString text = QString::fromStdString(best->method);
  if (!best->parameter.empty()) text += " (" + QString::fromStdString(best->parameter) + ")";
  text += "\ntime: " + seconds_text(best->seconds_per_evaluation) +
          (fam == "field" ? " per field" : " per evaluation");
  if (best->error_median <= 0)
    text += QString("\nmedian error: 0 (exact; drawn at %1)").arg(number(kExactErrorFloor));
  else
    text += "\nmedian error: " + number(best->error_median) + unit +
            QString::fromStdString(best->error_unit == "relative" ? " (relative)" : "");
  text += "\np99: " + number(best->error_p99) + ", max: " + number(best->error_max);
  if (best->failures > 0) text += QString("\nnot ok: %1 of %2").arg(best->failures).arg(best->failures + best->samples);
  return text;
}

void MethodsView::on_hover(const QString& method, const QPointF& point, bool entered) {
  if (entered) QToolTip::showText(QCursor::pos(), pointTip(method, point), view_);
  else QToolTip::hideText();
}

void MethodsView::fill_table() {
  table_->setSortingEnabled(false);  // else rows move while they are filled
  table_->setRowCount(int(rows_.size()));
  for (int i = 0; i < int(rows_.size()); ++i) {
    const MethodRow& r = rows_[std::size_t(i)];
    int c = 0;
    for (const std::string& s : {r.family, r.method, r.parameter})
      table_->setItem(i, c++, new QTableWidgetItem(QString::fromStdString(s)));
    for (double v : {r.seconds_per_evaluation, r.error_median, r.error_p99, r.error_max})
      table_->setItem(i, c++, new NumberItem(v, QString::number(v, 'e', 2)));  // aligned mantissas
    table_->setItem(i, c++, new QTableWidgetItem(QString::fromStdString(r.error_unit)));
    table_->setItem(i, c++, new NumberItem(double(r.samples), QString::number(r.samples)));
    table_->setItem(i, c++, new NumberItem(double(r.failures), QString::number(r.failures)));
  }
  table_->setSortingEnabled(true);
}

MethodsWindow::MethodsWindow(QWidget* parent) : QDialog(parent, Qt::Window) {
  setObjectName("methodsWindow");
  setWindowTitle("Linkscape: speed against accuracy");
  auto* layout = new QVBoxLayout(this);
  view_ = new MethodsView(this);
  layout->addWidget(view_);
  // Esc closes a dialog already; Ctrl+W (and the platform's other Close keys) too.
  auto* close_key = new QShortcut(QKeySequence::Close, this);
  connect(close_key, &QShortcut::activated, this, &QWidget::close);
  const QScreen* screen = parent ? parent->screen() : QGuiApplication::primaryScreen();
  if (screen) resize(screen->availableGeometry().size() * 2 / 3);
}

void MethodsWindow::setRows(const std::vector<MethodRow>& rows, const QString& mechanism_title) {
  view_->setRows(rows);
  setWindowTitle("Linkscape: speed against accuracy, " + mechanism_title);
}

}  // namespace linkscape::gui
