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
// not observed is no evidence either way. Nor is a part drawn where the
// other pose draws nothing, explaining a surface that goes on past both
// outlines from the part's depth without a step (a table just behind the
// cup, seen square or at a slant, an occluder):
// a handle turned onto such a surface would otherwise win a comparison
// that the depth cannot settle. That check follows the surface past the
// outlines from each such pixel, so it is asked for (PoseDifference::kPart)
// where the poses differ by a part: a pose and its turns. Poses apart over their
// whole silhouettes (close rivals) differ on too many pixels for it, and
// their comparison measured the same without it.

#include "core/common/image.h"

namespace ihf {

// How two compared poses differ, which says whether a part drawn where
// the other pose draws nothing is checked for a surface going on past it.
enum class PoseDifference {
	kPart,       // a pose and its turn: the check runs
	kSilhouette, // close rivals, apart over their whole outlines: it does not
};

struct PartEvidence {
	int differing = 0;   // pixels where the renders differ
	int informative = 0; // of those, evidence for one of the two
	int forA = 0;
	int forB = 0;
};

// observed, renderA and renderB: the same window, 0 = no depth / not drawn.
PartEvidence comparePoseRenders(ImageView<const float> observed, ImageView<const float> renderA,
				ImageView<const float> renderB, float toleranceMm, PoseDifference difference);

} // namespace ihf
