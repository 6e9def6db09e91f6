#include "gui/window/probe_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QLabel>
#include <QMessageBox>
#include <QPushButton>
#include <QTextDocument>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/haptics.h"

#include "gui/window/profile_chart.h"
#include "render/mark_scene.h"
#include "render/slice_image.h"

namespace linkscape::gui {

namespace {

constexpr int kProfileSamples = 201;

QString number(double v) { return std::isnan(v) ? QObject::tr("no value") : QString::number(v, 'g', 5); }

QString point_text(const Eigen::Vector3d& p, const QString& unit) {
  return QString("(%1, %2, %3) %4").arg(number(p.x()), number(p.y()), number(p.z()), unit);
}

}  // namespace

ProbePanel::ProbePanel(render::MarkScene* marks, Hooks hooks, const QString& length_unit, QWidget* parent)
    : QWidget(parent), marks_(marks), hooks_(std::move(hooks)), unit_(length_unit) {
  auto* layout = new QVBoxLayout(this);
  auto* form = new QFormLayout;
  mode_box_ = new QComboBox;
  mode_box_->setObjectName("probeModeBox");
  mode_box_->addItems({tr("Read values"), tr("Ruler"), tr("Line probe")});
  mode_box_->setToolTip(tr("What a click in the view does (a drag still turns the camera). "
                           "Shift+click places a ruler end in any mode."));
  form->addRow(tr("Click"), mode_box_);
  hover_box_ = new QCheckBox(tr("Read on hover"));
  hover_box_->setObjectName("probeHoverBox");
  hover_box_->setToolTip(tr("Read the fields wherever the mouse rests over the slice, a surface or the linkage"));
  form->addRow(QString(), hover_box_);
  layout->addLayout(form);
  readout_ = new QLabel(tr("Click the slice, a surface or the linkage to read the fields there."));
  readout_->setObjectName("probeReadout");
  readout_->setWordWrap(true);
  readout_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(readout_);
  ruler_label_ = new QLabel;
  ruler_label_->setObjectName("rulerLabel");
  ruler_label_->setWordWrap(true);
  layout->addWidget(ruler_label_);
  auto* line_form = new QFormLayout;
  field_box_ = new QComboBox;
  field_box_->setObjectName("probeFieldBox");
  field_box_->setToolTip(tr("The field plotted along the line probe's segment"));
  line_form->addRow(tr("Line probe of"), field_box_);
  layout->addLayout(line_form);
  chart_ = new ProfileChart;
  chart_->setToolTip(tr("The chosen field along the line probe's segment; gaps where no sample holds a value"));
  layout->addWidget(chart_, 1);
  export_button_ = new QPushButton(tr("Export CSV…"));
  export_button_->setObjectName("probeExportButton");
  export_button_->setEnabled(false);
  export_button_->setToolTip(tr("Write the line probe as CSV: distance, x, y, z, the field, with units in the header"));
  layout->addWidget(export_button_);

  connect(mode_box_, &QComboBox::currentIndexChanged, this, [this] { updateRuler(); });
  connect(hover_box_, &QCheckBox::toggled, this, &ProbePanel::hoverToggled);
  connect(field_box_, &QComboBox::currentTextChanged, this, [this] { updateProfile(); });
  connect(export_button_, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Export line probe"), "line-probe.csv", tr("CSV (*.csv)"));
    if (path.isEmpty()) return;
    QString error;
    if (!exportProfile(path, &error)) QMessageBox::warning(this, tr("Export line probe"), error);
  });
  updateRuler();
}

ProbePanel::Mode ProbePanel::mode() const { return Mode(mode_box_->currentIndex()); }
void ProbePanel::setMode(Mode mode) { mode_box_->setCurrentIndex(int(mode)); }
bool ProbePanel::hover() const { return hover_box_->isChecked(); }
QString ProbePanel::readout() const {
  QTextDocument doc;
  doc.setHtml(readout_->text());
  return doc.toPlainText();
}

std::optional<double> ProbePanel::rulerLength() const {
  if (!ruler_[0] || !ruler_[1]) return std::nullopt;
  return (*ruler_[1] - *ruler_[0]).norm();
}

void ProbePanel::pick(const Eigen::Vector3d& p, const QString& what, bool click, bool shift) {
  read(p, what);
  if (click && (shift || mode() == Mode::Ruler)) {
    place(ruler_, p);
    updateRuler();
  } else if (click && mode() == Mode::Line) {
    place(line_, p);
    updateProfile();
  }
  if (hooks_.marks_changed) hooks_.marks_changed();
}

// The first end, then the second; a third click starts a new segment.
void ProbePanel::place(std::optional<Eigen::Vector3d> (&ends)[2], const Eigen::Vector3d& p) {
  if (ends[0] && !ends[1]) {
    ends[1] = p;
  } else {
    ends[0] = p;
    ends[1].reset();
  }
}

void ProbePanel::read(const Eigen::Vector3d& p, const QString& what) {
  picked_ = p;
  picked_what_ = what;
  marks_->set_pick(p);
  QString source;
  const Field* field = hooks_.field_at ? hooks_.field_at(p, &source) : nullptr;
  sample_ = field ? render::probe_point(*field, p) : std::nullopt;
  const std::optional<render::ProbeSample>& sample = sample_;
  QString html = tr("<b>%1</b> on the %2").arg(point_text(p, unit_), what.toHtmlEscaped());
  if (!sample) {
    html += tr("<br>No field is sampled here (the slice and the surfaces' volume do not cover this point).");
  } else {
    html += tr("<br>From the %1's samples: trilinear between the samples around the point where they all hold a "
               "value, else the nearest sample (%2, %3, %4) at %5.")
                .arg(source)
                .arg(sample->nearest[0])
                .arg(sample->nearest[1])
                .arg(sample->nearest[2])
                .arg(point_text(sample->nearest_point, unit_));
    html += "<table cellspacing=4>";
    auto row = [&html](const render::ProbeValue& v, const QString& how) {
      QString value = v.label.empty() ? number(v.value) : QString::fromStdString(v.label);
      if (!v.unit.empty() && v.label.empty() && !std::isnan(v.value))
        value += v.unit == "deg" ? QString("°") : " " + QString::fromStdString(v.unit);  // as the Drive tab writes angles
      html += QString("<tr><td>%1</td><td align=right><b>%2</b></td><td><i>%3</i></td></tr>")
                  .arg(QString::fromStdString(v.title).toHtmlEscaped(), value.toHtmlEscaped(),
                       std::isnan(v.value) ? QString() : how);
    };
    for (const render::ProbeValue& v : sample->values) row(v, render::to_string(v.sampling));
    // The haptic measures the sampled field lacks (its extras may be the
    // device's stops alone), computed at the point itself.
    const auto haptic = [](const Field::NamedArray& e) { return haptics::is_haptic_field(e.name); };
    const bool sampled_haptics = std::any_of(field->extras.begin(), field->extras.end(), haptic);
    const std::optional<Field> exact = !sampled_haptics && hooks_.haptics_at ? hooks_.haptics_at(p, *field) : std::nullopt;
    if (exact)
      if (const auto at = render::probe_point(*exact, p))
        for (const Field::NamedArray& e : exact->extras)
          if (haptic(e))
            if (const render::ProbeValue* v = at->find(e.name)) row(*v, tr("computed at the point"));
    html += "</table>";
    if (field_box_->count() == 0) fillFields(*field);
  }
  if (hooks_.pose_status) html += tr("<br>Device pose: %1").arg(hooks_.pose_status().toHtmlEscaped());
  readout_->setText(html);
}

void ProbePanel::updateRuler() {
  const std::optional<double> length = rulerLength();
  const QString text = length ? QString("%1 %2").arg(number(*length), unit_) : QString();
  marks_->set_ruler(ruler_[0], ruler_[1], text.toStdString());
  if (length)
    ruler_label_->setText(tr("Ruler: %1 between %2 and %3").arg(text, point_text(*ruler_[0], unit_),
                                                               point_text(*ruler_[1], unit_)));
  else if (ruler_[0])
    ruler_label_->setText(tr("Ruler: from %1; click the second point").arg(point_text(*ruler_[0], unit_)));
  else
    ruler_label_->setText(mode() == Mode::Ruler ? tr("Ruler: click the first point")
                                                : tr("Ruler: Shift+click two points"));
  if (hooks_.marks_changed) hooks_.marks_changed();
}

void ProbePanel::fillFields(const Field& field) {
  const QVariant kept = field_box_->currentData();
  QSignalBlocker quiet(field_box_);
  field_box_->clear();
  // Titled as the colour bar and the chart title them ("c(J)"), by name underneath.
  for (const std::string& name : render::probed_fields(field))
    field_box_->addItem(QString::fromStdString(name == "reachable" ? name : render::field_title(field, name)),
                        QString::fromStdString(name));
  const int k = field_box_->findData(kept);
  field_box_->setCurrentIndex(k >= 0 ? k : 0);
}

void ProbePanel::updateProfile() {
  profile_.reset();
  marks_->set_probe(line_[0], line_[1], std::string());
  export_button_->setEnabled(false);
  if (!line_[0] || !line_[1]) {
    chart_->clearProfile();
    return;
  }
  QString source;
  // The field holding the first end; points beyond it have no value.
  const Field* field = hooks_.field_at ? hooks_.field_at(*line_[0], &source) : nullptr;
  if (!field) {
    chart_->clearProfile();
    chart_->chart()->setTitle(tr("No field is sampled at the segment's first end"));
    return;
  }
  fillFields(*field);
  try {
    profile_ = render::probe_line(*field, field_box_->currentData().toString().toStdString(), *line_[0], *line_[1],
                                  kProfileSamples);
  } catch (const std::invalid_argument& e) {
    chart_->clearProfile();
    chart_->chart()->setTitle(QString::fromStdString(e.what()));
    return;
  }
  chart_->showProfile(*profile_);
  const double length = (*line_[1] - *line_[0]).norm();
  marks_->set_probe(line_[0], line_[1], QString("%1 %2").arg(number(length), unit_).toStdString());
  export_button_->setEnabled(true);
}

void ProbePanel::refresh() {
  if (picked_) read(*picked_, picked_what_);
  if (line_[1]) updateProfile();
}

void ProbePanel::clearPoints() {
  for (auto* ends : {&ruler_, &line_})
    for (auto& e : *ends) e.reset();
  picked_.reset();
  marks_->set_pick(std::nullopt);
  updateRuler();
  updateProfile();
}

bool ProbePanel::exportProfile(const QString& path, QString* error) {
  try {
    if (!profile_) throw std::invalid_argument(tr("There is no line probe to export: pick two points in Line probe mode.").toStdString());
    render::write_profile_csv(*profile_, path.toStdString());
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

}  // namespace linkscape::gui
