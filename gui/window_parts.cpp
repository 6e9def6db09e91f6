#include "gui/window_parts.h"

#include <QComboBox>
#include <QDockWidget>
#include <QMainWindow>
#include <QMessageBox>
#include <stdexcept>

#include "gui/main_window.h"
#include "gui/methods_panel.h"
#include "gui/pathos2_window.h"

namespace linkscape::gui {

QDockWidget* add_dock(QMainWindow* window, const QString& title, const QString& name, QWidget* content) {
  auto* d = new QDockWidget(title, window);
  d->setObjectName(name);
  d->setWidget(content);
  window->addDockWidget(Qt::RightDockWidgetArea, d);
  return d;
}

MethodsPanel* add_methods_dock(QMainWindow* window, const Preset& preset, QDockWidget* tab_with) {
  auto* panel = new MethodsPanel;
  panel->setMechanism(preset);
  QDockWidget* d = add_dock(window, QObject::tr("Methods"), "methodsDock", panel);
  window->tabifyDockWidget(tab_with, d);
  return panel;
}

QComboBox* make_preset_chooser(QWidget* window, const Preset& current) {
  auto* box = new QComboBox;
  box->setObjectName("presetBox");
  for (const auto& name : available_presets()) box->addItem(QString::fromStdString(name));
  const QString current_name = QString::fromStdString(current.source.stem().string());
  box->setCurrentText(current_name.isEmpty() ? QString::fromStdString(current.mechanism) : current_name);
  box->setToolTip(QString::fromStdString(current.title));
  QObject::connect(box, &QComboBox::activated, window, [window, box, current_name] {
    const QString chosen = box->currentText();
    if (chosen == current_name) return;
    try {
      const Preset preset = load_preset(chosen.toStdString());
      QWidget* next = preset.mechanism == pathos2::kMechanismName ? static_cast<QWidget*>(new Pathos2Window(preset))
                                                                   : static_cast<QWidget*>(new MainWindow(preset));
      next->setAttribute(Qt::WA_DeleteOnClose);
      next->setGeometry(window->geometry());
      next->show();
      window->close();
    } catch (const std::invalid_argument& e) {
      const QSignalBlocker block(box);
      box->setCurrentText(current_name);
      QMessageBox::warning(window, QObject::tr("Cannot open preset"), QString::fromStdString(e.what()));
    }
  });
  return box;
}

}  // namespace linkscape::gui
