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

// The sides of box (x, y, w, h pixels) on the border of a width x height frame.
inline OpenSides openSidesOf(int x, int y, int w, int h, int width, int height)
{
	return {x <= 0, y <= 0, x + w >= width, y + h >= height};
}

} // namespace ihf
