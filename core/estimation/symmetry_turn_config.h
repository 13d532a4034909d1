// SPDX-License-Identifier: MIT
#pragma once

// Settings of the rival turns of nearly symmetric objects
// (symmetry_rivals.h).

#include <algorithm>
#include <cmath>

namespace ihf {

struct SymmetryTurnConfig {
	bool enabled = true;
	float stepDeg = 15;     // turns tried about a continuous axis
	int rounds = 3;         // comparisons at most (each after a turn won)
	int polishRivals = 2;   // turns the best does not clearly beat, polished and compared again
	int closeRivals = 4;    // the best-scoring distinct hypotheses, compared with the best before its turns
	float closeLoss = 0.05f; // a winning close rival replaces the best if, polished, it scores at most this less
	int minPixels = 12;     // a lead of fewer pixels neither replaces the best nor decides
	float decisiveShare = 0.5f; // the best is certain this share of the informative pixels ahead (three to one)
	float preferShare = 0.34f;  // a rival this share ahead replaces the best (two to one)
	float ambiguousConfidence = 0.5f; // an ambiguous pose's confidence is scaled by this
};

// Whether evidence `ahead` leads `behind` by minPixels and by `share` of
// the informative pixels.
inline bool leadsBy(int ahead, int behind, int informative, float share, const SymmetryTurnConfig &c)
{
	return ahead - behind >= std::max(c.minPixels, static_cast<int>(std::ceil(share * informative)));
}

// A rival replaces the best on a lead of preferShare (the depth favours it
// two to one); the best beats a rival, and is certain of it, only on the
// wider lead of decisiveShare.
inline bool preferredBy(int ahead, int behind, int informative, const SymmetryTurnConfig &c)
{
	return leadsBy(ahead, behind, informative, c.preferShare, c);
}

inline bool decisivelyBy(int ahead, int behind, int informative, const SymmetryTurnConfig &c)
{
	return leadsBy(ahead, behind, informative, c.decisiveShare, c);
}

} // namespace ihf
