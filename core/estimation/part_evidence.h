// SPDX-License-Identifier: MIT
#pragma once

// Two poses compared where they differ. A pose and its rival turned about a
// near-symmetry axis (near_symmetry.h) render alike but for a small part (a
// cup's handle): the whole-silhouette score (hypothesis_score.h) hears that
// part among all the pixels where the two agree, and not at all where one
// of them draws nothing (the score counts drawn pixels only, so a cup whose
// handle is turned out of sight loses nothing for the handle the sensor
// sees). Here only the pixels where the two renders differ are looked at
// (one draws and the other does not, or their depths lie more than
// toleranceMm apart), and each observed pixel there is evidence for the pose
// that explains it (its render within toleranceMm of the depth) and the
// other does not, or against a pose the sensor sees through (the depth lies
// behind its render). A pixel observed in front of both (an occluder) or
// not observed is no evidence either way.

#include "core/common/image.h"

namespace ihf {

struct PartEvidence {
	int differing = 0;   // pixels where the renders differ
	int informative = 0; // of those, evidence for one of the two
	int forA = 0;
	int forB = 0;
};

// observed, renderA and renderB: the same window, 0 = no depth / not drawn.
PartEvidence comparePoseRenders(ImageView<const float> observed, ImageView<const float> renderA,
				ImageView<const float> renderB, float toleranceMm);

} // namespace ihf
