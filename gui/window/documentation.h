// Help > Documentation (F1): the user guide — README.md and docs/*.md,
// installed in share/doc/linkscape — shown in the window as formatted text,
// with its links between pages followed in place and web links opened in
// the browser; Help > Keyboard shortcuts: every menu entry's shortcut.
#pragma once

#include <QDialog>
#include <QString>
#include <filesystem>

class QMenuBar;
class QTextBrowser;

namespace linkscape::gui {

// The guide's first page: README.md installed beside the program
// (../share/doc/linkscape), else in the source tree it was built from;
// empty when neither exists.
std::filesystem::path documentation_home();

class DocumentationBrowser : public QDialog {
  Q_OBJECT
 public:
  DocumentationBrowser(const std::filesystem::path& home, QWidget* parent = nullptr);
  QTextBrowser* browser() const { return browser_; }

 private:
  QTextBrowser* browser_;
};

// Opens the guide (one browser per window, raised when open again), or says
// where to read it when no copy is installed.
void show_documentation(QWidget* parent);

// "File > Save session    Ctrl+S", one line per menu entry with a shortcut,
// in menu order.
QString shortcut_table(const QMenuBar* menus);
void show_shortcuts(QWidget* parent, const QMenuBar* menus);

}  // namespace linkscape::gui
