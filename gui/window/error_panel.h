// The panel above the 3-D view that says why a file did not load: a
// red-tinted frame with a title, the file's path and the whole message
// (word-wrapped, selectable, so it can be copied into an editor or an
// issue), a Reload button and a Dismiss button. Hidden until an error is
// shown; the window it sits in is left as it was.
#pragma once

#include <QFrame>
#include <QString>

class QLabel;
class QMainWindow;
class QPushButton;

namespace linkscape::gui {

class ErrorPanel : public QFrame {
  Q_OBJECT

 public:
  explicit ErrorPanel(QWidget* parent = nullptr);
  // A panel above `view` in the centre of `window`, where it is seen.
  static ErrorPanel* placeAbove(QMainWindow* window, QWidget* view);

  // Shows the panel: `title` in bold ("Cannot reload the mechanism"), then
  // the file and what is wrong with it.
  void showError(const QString& title, const QString& path, const QString& message);
  QString path() const { return path_; }
  QString text() const;  // the title, the path and the message, as shown

 signals:
  // Reload pressed: the window reads `path` again.
  void reloadRequested(const QString& path);

 private:
  QString path_;
  QLabel *title_ = nullptr, *path_label_ = nullptr, *message_ = nullptr;
  QPushButton* reload_ = nullptr;
};

}  // namespace linkscape::gui
