// The window's Fit tab: sizing the window's device to the Task tab's task
// and criteria (core/fit.h), built from the device's description: which
// design parameters are free and their bounds, groups held equal, and the
// mode (the smallest size, or the largest ratio at a size). Run works off
// the GUI thread with progress and Cancel; the answer is shown as the same
// report and chart as `linkscape fit` (gui/figures/fit_report.h), can be applied to
// the window's design and exported (chart as PNG/SVG/PDF, CSV).
#pragma once

#include <QWidget>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/fit.h"
#include "gui/window/background.h"
#include "gui/window/session.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPlainTextEdit;
class QProgressBar;
class QPushButton;

namespace linkscape::gui {

class TaskPanel;

class FitPanel : public QWidget {
  Q_OBJECT

 public:
  enum class Mode { SmallestSize, LargestMarginAtSize };

  // `task` gives the task and criteria each Run uses.
  explicit FitPanel(const TaskPanel* task, QWidget* parent = nullptr);
  ~FitPanel() override;  // cancels and joins a running search

  // The window's design: the parameters held, and the pose whose
  // coordinates beyond x, y, z the task holds. The first call builds a row
  // per design parameter (free: those the size counts; bounds: the design
  // panel's range); later calls keep what the user set.
  void setDevice(const Preset& preset, const Eigen::VectorXd& pose);

  // What the next Run searches; each throws std::invalid_argument for a
  // name the device does not show or bad bounds.
  void setFree(const std::vector<std::string>& names);
  void setBounds(const std::string& name, double lo, double hi);
  void setEqual(const std::string& groups);  // "L1,L2" (groups separated by ';')
  void setMode(Mode mode, double size = 0);
  void setCentreFree(bool free);
  // Where a free centre may go (core/task.h CentreRegion text; empty:
  // anywhere). Throws std::invalid_argument for bad text.
  void setCentreRegion(const std::string& region);
  std::string centreRegion() const;
  // What a session keeps of the tab, and back: the free parameters, their
  // bounds, the groups held equal (the last valid text: groups of the
  // device's parameters), the mode, the size, whether the centre is free
  // and where (the last valid region text). applySetting throws
  // std::invalid_argument (nothing changed) for a parameter the device does
  // not have or a bad region.
  FitSetting setting() const;
  void applySetting(const FitSetting& setting);
  // The last result as a session keeps it (none before a run), and back:
  // a result from a session shows its report and verdict and Apply sets its
  // design; the chart and the exports need a Run.
  std::optional<FitOutcome> outcome() const;
  void applyOutcome(const FitOutcome& outcome);
  bool showsSavedOutcome() const { return saved_.has_value(); }
  // The sampling (defaults: those of linkscape fit).
  void setSearchSettings(const task::InscribedOptions& inscribed, int task_resolution, double tolerance);

  bool isRunning() const { return worker_.running(); }
  const std::optional<fit::Problem>& problem() const { return problem_; }
  const std::optional<fit::Result>& result() const { return result_; }
  // The chosen design's free parameters (or the closest one's); empty before a result.
  std::map<std::string, double> chosenDesign() const;
  // Where the search placed the task for that design (centre free), else empty.
  std::optional<Eigen::Vector3d> chosenCentre() const;
  QString statusText() const;
  QString reportText() const;

  // Throw std::invalid_argument without a result, std::runtime_error when the file cannot be written.
  void exportChart(const std::filesystem::path& path) const;
  void exportCsv(const std::filesystem::path& path) const;

 public slots:
  void run();     // no-op while running; bad input is shown in the status
  void cancel();  // the search stops after the design it is evaluating
  void applyDesign();  // asks the window to take chosenDesign() (and the task to move to chosenCentre())

 signals:
  void runFinished(bool completed);  // false when cancelled or failed
  void applyRequested(const std::map<std::string, double>& parameters);

 private:
  struct ParameterRow;
  fit::Problem makeProblem() const;  // throws std::invalid_argument
  void finish(std::optional<fit::Result> result, const QString& message);
  void syncMode();

  const TaskPanel* task_;
  Preset preset_;
  Eigen::VectorXd pose_;
  std::vector<ParameterRow> rows_;
  task::InscribedOptions inscribed_;
  int task_resolution_ = task::kTaskResolution;
  double tolerance_ = 1e-3;

  void keepValidEqualGroups() const;      // the box's groups, when they name the device's parameters
  mutable std::string last_valid_equal_;  // setting()'s Hold equal groups
  mutable std::string last_valid_region_;  // setting()'s centre region
  std::optional<FitOutcome> saved_;       // a session's result shown, until the next run
  std::optional<fit::Problem> problem_;  // of the result shown (or the run in flight)
  std::optional<fit::Result> result_;

  QWidget* parameters_ = nullptr;
  QLineEdit* equal_edit_ = nullptr;
  QComboBox* mode_box_ = nullptr;
  QDoubleSpinBox* size_box_ = nullptr;
  QCheckBox* centre_free_ = nullptr;
  QLineEdit* region_edit_ = nullptr;
  QLabel* region_label_ = nullptr;
  QPushButton* run_button_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* status_ = nullptr;
  QPlainTextEdit* report_ = nullptr;
  QWidget* chart_ = nullptr;
  QPushButton* apply_button_ = nullptr;
  QPushButton* export_chart_button_ = nullptr;
  QPushButton* export_csv_button_ = nullptr;
  // Last, so a search in flight is cancelled and joined before the rest goes.
  BackgroundTask worker_;  // its end disables Cancel
};

}  // namespace linkscape::gui
