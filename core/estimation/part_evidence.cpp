// SPDX-License-Identifier: MIT
#include "core/estimation/part_evidence.h"

#include <algorithm>
#include <cmath>

namespace ihf {

namespace {

// A surface is followed past the outline of what the two poses draw, in
// each of eight directions, to the pixels 3 and 4 beyond it: past the few
// pixels where a depth sensor blurs an edge (a structured-light matcher's
// half window, the fattening of the nearer surface). An outline farther
// than kMaxWalk pixels away is not followed.
constexpr int kBeyondNear = 3, kBeyondFar = 4, kMaxWalk = 16;

// Whether the surface the sensor sees at (x, y), at depth o, goes on past
// both poses' outlines: of the observed pixels found there that neither
// pose draws, more are reached from (x, y) along the same surface than
// across a step (a table behind the object, an occluder). The surface is
// the same where the pixel lies within toleranceMm of o, or where the
// depth on the way there never steps by more than toleranceMm from one
// observed pixel to the next: a table or an occluder's face seen at a
// slant drifts away from o by a few mm a pixel, and would otherwise read
// as an edge. A part drawn there explains a surface that is there anyway.
// A part the sensor really sees ends at its outline, where the depth
// steps to the background's (a blurred or mixed edge pixel halves the
// step, a part in front of its background by more than twice the
// tolerance still shows one).
bool surfaceGoesOn(ImageView<const float> observed, ImageView<const float> renderA,
		   ImageView<const float> renderB, int x, int y, float o, float toleranceMm)
{
	const auto inside = [&](int u, int v) { return u >= 0 && v >= 0 && u < observed.width && v < observed.height; };
	const auto drawn = [&](int u, int v) { return renderA.at(u, v) > 0 || renderB.at(u, v) > 0; };
	int same = 0, other = 0;
	for (int dy = -1; dy <= 1; ++dy)
		for (int dx = -1; dx <= 1; ++dx) {
			if (dx == 0 && dy == 0)
				continue;
			int outline = 1;
			while (outline <= kMaxWalk && inside(x + dx * outline, y + dy * outline) &&
			       drawn(x + dx * outline, y + dy * outline))
				++outline;
			if (outline > kMaxWalk)
				continue;
			// The depth followed pixel by pixel from (x, y): whether it
			// stepped on the way (missing depth is passed over).
			float last = o;
			bool stepped = false;
			for (int k = 1; k <= outline + kBeyondFar; ++k) {
				const int u = x + dx * k, v = y + dy * k;
				if (!inside(u, v))
					break;
				const float n = observed.at(u, v);
				if (!(n > 0))
					continue;
				stepped = stepped || std::abs(n - last) > toleranceMm;
				last = n;
				if (k < outline + kBeyondNear || drawn(u, v))
					continue;
				if (!stepped || std::abs(n - o) <= toleranceMm)
					++same;
				else
					++other;
			}
		}
	return same > other;
}

} // namespace

PartEvidence comparePoseRenders(ImageView<const float> observed, ImageView<const float> renderA,
				ImageView<const float> renderB, float toleranceMm, PoseDifference difference)
{
	PartEvidence e;
	for (int y = 0; y < observed.height; ++y)
		for (int x = 0; x < observed.width; ++x) {
			const float a = renderA.at(x, y), b = renderB.at(x, y);
			const bool drawnA = a > 0, drawnB = b > 0;
			if (drawnA == drawnB && (!drawnA || std::abs(a - b) <= toleranceMm))
				continue;
			++e.differing;
			const float o = observed.at(x, y);
			if (!(o > 0))
				continue;
			const bool explainsA = drawnA && std::abs(o - a) <= toleranceMm;
			const bool explainsB = drawnB && std::abs(o - b) <= toleranceMm;
			const bool throughA = drawnA && o > a + toleranceMm;
			const bool throughB = drawnB && o > b + toleranceMm;
			const bool forA = (explainsA && !explainsB) || (throughB && !throughA);
			const bool forB = (explainsB && !explainsA) || (throughA && !throughB);
			if (forA == forB)
				continue;
			// A part that explains the depth where the other pose draws
			// nothing is evidence only where that surface is its own.
			if (difference == PoseDifference::kPart && !(forA ? drawnB : drawnA) &&
			    surfaceGoesOn(observed, renderA, renderB, x, y, o, toleranceMm))
				continue;
			++e.informative;
			if (forA)
				++e.forA;
			else
				++e.forB;
		}
	return e;
}

} // namespace ihf
