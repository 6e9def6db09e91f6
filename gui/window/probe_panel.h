// The Probe panel: what a pick in the view reads and measures.
//  - Read: a click (or the resting mouse, with hover on) shows the point,
//    every field's value there with its unit and how it was sampled, the
//    sample's status and the device's pose status.
//  - Ruler: two clicks (or Shift+clicks in any mode) measure the distance
//    between two points, drawn in the view with its length.
//  - Line probe: two clicks set a segment; the chosen field is plotted along
//    it and can be exported as CSV.
// Values come from the field holding the point: the slice where the point
// lies on it, else the sampled volume of the workspace surfaces.
#pragma once

#include <QString>
#include <QWidget>
#include <functional>
#include <optional>

#include <Eigen/Core>

#include "render/field_probe.h"

class QComboBox;
class QCheckBox;
class QLabel;
class QPushButton;

namespace linkscape::render {
class MarkScene;
}

namespace linkscape::gui {

class ProfileChart;

class ProbePanel : public QWidget {
  Q_OBJECT

 public:
  enum class Mode { Read = 0, Ruler = 1, Line = 2 };
  struct Hooks {
    // The field holding `p` and what it is ("slice", "volume"), or null.
    std::function<const Field*(const Eigen::Vector3d& p, QString* source)> field_at;
    std::function<QString()> pose_status;  // "ok", or why the last pose was refused
    // The haptic measures computed exactly at `p` (a one-sample field with
    // them as extras) for a field that lacks them, or nothing.
    std::function<std::optional<Field>(const Eigen::Vector3d& p, const Field& near)> haptics_at;
    std::function<void()> marks_changed;   // the view must draw again
  };

  ProbePanel(render::MarkScene* marks, Hooks hooks, const QString& length_unit, QWidget* parent = nullptr);

  Mode mode() const;
  void setMode(Mode mode);
  bool hover() const;
  // A point of the scene picked (`what` was hit). Clicks in Ruler or Line
  // mode, and Shift+clicks, place an end; every pick is read.
  void pick(const Eigen::Vector3d& p, const QString& what, bool click, bool shift);
  // The fields changed: the read-out and the profile are read again.
  void refresh();
  // Forget every point (a new device).
  void clearPoints();

  QString readout() const;                  // the text shown (plain)
  // What the last read found (nothing: no field holds the point).
  const std::optional<render::ProbeSample>& sample() const { return sample_; }
  std::optional<double> rulerLength() const;
  const std::optional<render::LineProfile>& profile() const { return profile_; }
  ProfileChart* chart() const { return chart_; }
  // Writes the profile as CSV (render::write_profile_csv); false with the
  // reason in `error` when there is none or the file cannot be written.
  bool exportProfile(const QString& path, QString* error = nullptr);

 signals:
  void hoverToggled(bool on);

 private:
  void read(const Eigen::Vector3d& p, const QString& what);
  void place(std::optional<Eigen::Vector3d> (&ends)[2], const Eigen::Vector3d& p);
  void updateRuler();
  void updateProfile();
  void fillFields(const Field& field);

  render::MarkScene* marks_;
  Hooks hooks_;
  QString unit_;
  std::optional<Eigen::Vector3d> ruler_[2], line_[2], picked_;
  QString picked_what_;
  std::optional<render::LineProfile> profile_;
  std::optional<render::ProbeSample> sample_;
  QComboBox *mode_box_ = nullptr, *field_box_ = nullptr;
  QCheckBox* hover_box_ = nullptr;
  QLabel *readout_ = nullptr, *ruler_label_ = nullptr;
  QPushButton* export_button_ = nullptr;
  ProfileChart* chart_ = nullptr;
};

}  // namespace linkscape::gui
