// Help menu: the versions of the program and its libraries; how the device
// in the window is solved. The guide itself is gui/window/documentation.h.
#pragma once

#include <string>

#include "core/preset.h"

class QWidget;

namespace linkscape::gui {

void show_about(QWidget* parent);
// About this mechanism: for a described device what `linkscape describe`
// prints (each leg's pattern or "numeric", travel, branch rules, reach
// bounds, mobility); for a compiled one, that it is C++ and where.
std::string mechanism_summary(const Preset& preset);
void show_mechanism(QWidget* parent, const Preset& preset);

}  // namespace linkscape::gui
