// Choosing another preset in a window: the window of that preset's mechanism
// opens in its place (each mechanism has its own window class).
#pragma once

#include "core/preset.h"

class QComboBox;
class QWidget;

namespace linkscape::gui {

// A combo box of every preset on the search path, showing `current`. Picking
// another one opens its window (same size and place) and closes `window`; a
// preset that fails to load leaves everything as it was and says why.
QComboBox* make_preset_chooser(QWidget* window, const Preset& current);

}  // namespace linkscape::gui
