// SPDX-License-Identifier: MIT
#pragma once

// One box of a frame, as an upstream detector gives it: the object it
// shows, where, and the detector's own track of it if it keeps one.

#include <array>

namespace ihf::app {

struct FrameBox {
	int objId = 0;
	std::array<double, 4> bbox{0, 0, 0, 0}; // x, y, w, h pixels
	int trackId = 0; // the detector's track, 0: none
};

} // namespace ihf::app
