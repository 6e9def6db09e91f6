// Interaction latencies of the window, measured the way a user meets them:
// from a change of a control to the frame that shows its result.
#pragma once

#include <iosfwd>

namespace linkscape::gui {

class MechanismWindow;

// Drives `window` (shown, event loop not yet running) through a fixed script
// and prints a table to `out`: actuator slider to frame (the slider held
// down as in a drag; device only, and with slice and isosurfaces), a design parameter (the first in the design
// panel) to the coarse and to the full slice on screen and to the full
// isosurfaces on screen (with and without surface smoothing, alternating).
// Returns the process exit code.
int run_latency_probe(MechanismWindow& window, std::ostream& out);

}  // namespace linkscape::gui
