// Help menu: the versions of the program and its libraries; where the
// documentation is (the docs folder of the source tree when there is one,
// else the manual page).
#pragma once

class QWidget;

namespace linkscape::gui {

void show_about(QWidget* parent);
void show_documentation(QWidget* parent);

}  // namespace linkscape::gui
