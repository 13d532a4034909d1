// SPDX-License-Identifier: MIT
#pragma once

// Settings of the rival turns of nearly symmetric objects
// (symmetry_rivals.h).

namespace ihf {

struct SymmetryTurnConfig {
	bool enabled = true;
	float stepDeg = 15;     // turns tried about a continuous axis
	int rounds = 3;         // comparisons at most (each after a turn won)
	int polishRivals = 2;   // turns the best does not clearly beat, polished and compared again
	int closeRivals = 4;    // the best-scoring distinct hypotheses, compared with the best before its turns
	float closeLoss = 0.05f; // a winning close rival replaces the best if, polished, it scores at most this less
	int minPixels = 12;     // evidence this many pixels ahead is decisive,
	float decisiveShare = 0.5f; // and this share of the informative pixels
	float ambiguousConfidence = 0.5f; // an ambiguous pose's confidence is scaled by this
};

} // namespace ihf
