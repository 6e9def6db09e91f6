#include "gui/window/error_panel.h"

#include <QHBoxLayout>
#include <QLabel>
#include <QMainWindow>
#include <QPushButton>
#include <QStyle>
#include <QVBoxLayout>

namespace linkscape::gui {

namespace {

// Selectable plain text (a message may hold '<'), wrapped at the panel's
// width: the Ignored width keeps a long path or message from widening the window.
QLabel* text_label(QWidget* parent, const QString& name) {
  auto* label = new QLabel(parent);
  label->setObjectName(name);
  label->setTextFormat(Qt::PlainText);
  label->setWordWrap(true);
  label->setTextInteractionFlags(Qt::TextSelectableByMouse | Qt::TextSelectableByKeyboard);
  label->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  return label;
}

}  // namespace

ErrorPanel::ErrorPanel(QWidget* parent) : QFrame(parent) {
  setObjectName("errorPanel");
  setFrameShape(QFrame::StyledPanel);
  setStyleSheet("#errorPanel { margin: 4px; background: #fdecea; border: 1px solid #c62828; border-radius: 4px; }"
                "#errorPanel QLabel { color: #5f0b0b; background: transparent; border: none; }");
  auto* icon = new QLabel(this);
  icon->setPixmap(style()->standardIcon(QStyle::SP_MessageBoxCritical).pixmap(24, 24));
  icon->setAlignment(Qt::AlignTop);
  title_ = text_label(this, "errorTitleLabel");
  QFont bold = title_->font();
  bold.setBold(true);
  title_->setFont(bold);
  path_label_ = text_label(this, "errorPathLabel");
  message_ = text_label(this, "errorMessageLabel");
  for (QLabel* l : {title_, path_label_, message_})
    l->setToolTip(tr("Select the text to copy it"));
  reload_ = new QPushButton(tr("Reload"), this);
  reload_->setObjectName("errorReloadButton");
  reload_->setToolTip(tr("Read the file again (after fixing it)"));
  auto* dismiss = new QPushButton(tr("Dismiss"), this);
  dismiss->setObjectName("errorDismissButton");
  dismiss->setToolTip(tr("Hide this message; the device shown stays as it is"));

  auto* top = new QHBoxLayout;
  top->addWidget(title_, 1);
  top->addWidget(reload_);
  top->addWidget(dismiss);
  auto* text = new QVBoxLayout;
  text->addLayout(top);
  text->addWidget(path_label_);
  text->addWidget(message_);
  auto* row = new QHBoxLayout(this);
  row->setContentsMargins(10, 8, 10, 8);
  row->addWidget(icon, 0, Qt::AlignTop);
  row->addLayout(text, 1);

  connect(reload_, &QPushButton::clicked, this, [this] { emit reloadRequested(path_); });
  connect(dismiss, &QPushButton::clicked, this, &QWidget::hide);
  hide();
}

void ErrorPanel::showError(const QString& title, const QString& path, const QString& message) {
  path_ = path;
  title_->setText(title);
  path_label_->setText(tr("File: %1").arg(path));
  path_label_->setVisible(!path.isEmpty());
  message_->setText(message);
  reload_->setEnabled(!path.isEmpty());
  reload_->setToolTip(tr("Read %1 again (after fixing it)").arg(path));
  show();
}

QString ErrorPanel::text() const { return title_->text() + "\n" + path_label_->text() + "\n" + message_->text(); }

ErrorPanel* ErrorPanel::placeAbove(QMainWindow* window, QWidget* view) {
  auto* centre = new QWidget(window);
  auto* column = new QVBoxLayout(centre);
  column->setContentsMargins(0, 0, 0, 0);
  column->setSpacing(0);
  auto* panel = new ErrorPanel(centre);
  column->addWidget(panel);
  column->addWidget(view, 1);
  window->setCentralWidget(centre);
  return panel;
}

}  // namespace linkscape::gui
