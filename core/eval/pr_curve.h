// SPDX-License-Identifier: MIT
#pragma once

// Precision/recall over a confidence threshold, and the best F1 (the
// paper's per-z_omega score). An estimate is correct when it was matched to
// a ground-truth instance with error <= maxError; unmatched estimates carry
// an infinite error. For each distinct score s (descending) the returned set
// is every estimate with score >= s:
//   precision = correct returned / returned
//   recall    = correct returned / numGt
//   F1        = 2 P R / (P + R), 0 when P + R = 0
// The best F1 is the maximum over thresholds, 0 if nothing is returned.

#include <span>
#include <vector>

namespace ihf {

struct ScoredOutcome {
	double score = 0;
	double error = 0; // +inf for an unmatched estimate
};

struct PrPoint {
	double threshold = 0;
	double precision = 0;
	double recall = 0;
	double f1 = 0;
};

// One point per distinct score, in decreasing threshold (increasing recall).
std::vector<PrPoint> prCurve(std::span<const ScoredOutcome> outcomes, size_t numGt,
			     double maxError);

double bestF1(std::span<const PrPoint> curve);

// Correct matched estimates over all instances, ignoring the score
// (the ADD(-S)-0.1d recall when maxError = 0.1 diameter).
double recallAt(std::span<const ScoredOutcome> outcomes, size_t numGt, double maxError);

} // namespace ihf
