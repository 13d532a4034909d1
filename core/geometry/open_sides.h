// SPDX-License-Identifier: MIT
#pragma once

namespace ihf {

// Sides of the given box that lie on the frame border. A detector clips its
// box there, so the object may run past such a side: overhang beyond it is
// not evidence against a pose.
struct OpenSides {
	bool left = false;
	bool top = false;
	bool right = false;
	bool bottom = false;
};

} // namespace ihf
