// The interactive speed-against-accuracy view of the method harness (Qt
// Charts), used by the Methods panel and by its enlarged window: one family
// at a time (a chooser), log10 of time per evaluation against log10 of the
// median error (axes labelled in decades), one scatter series per method, the
// family's Pareto front as a dashed staircase, a legend that wraps under the
// chart, rubber-band zoom (double-click or Reset zooms out), a tooltip with
// method, time and error on hover; below it a table of every row, sortable by
// every column (numbers numerically).
//
// Exact results (error 0) are drawn at kExactErrorFloor (gui/figures/method_chart.h)
// and their tooltip says so; rows with a non-finite or zero time or a
// non-finite error are not plotted, and a note under the chart counts them.
#pragma once

#include <QDialog>
#include <QPointF>
#include <QString>
#include <QStringList>
#include <QWidget>
#include <vector>

#include "core/method_harness.h"

class QChart;
class QChartView;
class QComboBox;
class QLabel;
class QTableWidget;

namespace linkscape::gui {

class MethodsView : public QWidget {
  Q_OBJECT

 public:
  explicit MethodsView(QWidget* parent = nullptr);

  // Shows `rows` (copied); keeps the chosen family when the new rows have it.
  void setRows(const std::vector<methods::MethodRow>& rows);
  const std::vector<methods::MethodRow>& rows() const { return rows_; }

  // Families in the order the rows first name them; the charted one.
  QStringList families() const;
  QString family() const;
  void setFamily(const QString& family);

  QChart* chart() const;
  QTableWidget* table() const { return table_; }
  QString note() const;

  // The hover text of the charted point `point` (log10 of time and of the
  // drawn error, the chart's coordinates) of the series named `method`:
  // method, parameter, time and error; empty if the family has no such point.
  QString pointTip(const QString& method, const QPointF& point) const;

 public slots:
  void resetZoom();

 private:
  void show_family();
  void fill_table();
  void fit_ticks();
  void on_hover(const QString& method, const QPointF& point, bool entered);

  std::vector<methods::MethodRow> rows_;
  QComboBox* family_ = nullptr;
  QChartView* view_ = nullptr;
  QLabel* legend_ = nullptr;
  QLabel* note_ = nullptr;
  QTableWidget* table_ = nullptr;
};

// The view in a top-level window of its own: resizable, titled, closed by
// Esc, Ctrl+W (the platform's Close key) or the window manager; starts at
// two thirds of the screen.
class MethodsWindow : public QDialog {
  Q_OBJECT

 public:
  explicit MethodsWindow(QWidget* parent = nullptr);
  MethodsView* view() const { return view_; }
  void setRows(const std::vector<methods::MethodRow>& rows, const QString& mechanism_title);

 private:
  MethodsView* view_ = nullptr;
};

}  // namespace linkscape::gui
