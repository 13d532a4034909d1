// SPDX-License-Identifier: MIT
#pragma once

// Initial clutter removal for the first registration. A box holds the
// object and whatever lies in front of and behind it (table, wall,
// occluders). Normalised into the unit cube as a whole, a far wall would
// stretch the cube's depth axis several times beyond the object's size, so
// the IBS lattice and the parts would see the object at a scale training
// never saw. The object occupies a depth slab no thicker than its diameter:
// the slabs of that thickness holding the most pixels are the candidates,
// each voted on separately (the refinement then uses Eq. 10's hypothesis
// range as the paper does).

#include <span>

#include "core/common/image.h"

namespace ihf {

struct DepthWindow {
	float nearMm = 0;
	float farMm = 0;
	int pixels = 0; // not already in a denser window
};

// Writes up to out.size() windows of thickness widthMm, densest first; a
// window's pixels do not count again for the later ones. Returns how many.
// hist is scratch of at least 2 entries (its size bounds the histogram's
// resolution).
size_t findDepthWindows(ImageView<const float> depth, float widthMm, std::span<int> hist,
			std::span<DepthWindow> out);

// Median depth of the pixels inside the window, to 1/64 of its thickness (0
// when it holds none). Only the central `share` of the image's width and
// height counts while it holds at least minPixels of the window's: the
// middle of a box is the object's, its rim the table's or the wall's.
float windowMedianDepth(ImageView<const float> depth, const DepthWindow &window, float share = 1.0f,
			int minPixels = 32);

} // namespace ihf
