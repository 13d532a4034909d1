// SPDX-License-Identifier: MIT
#pragma once

// Greedy assignment of pose estimates to ground-truth instances of one
// object in one image (BOP-style, but independent of the correctness
// threshold): estimates are taken in decreasing score (ties keep input
// order); each takes the still unmatched instance with the smallest error
// (ties: lowest instance index). Estimates left without an instance (more
// estimates than instances, e.g. duplicates) are false positives.

#include <vector>

#include <Eigen/Core>

namespace ihf {

struct MatchResult {
	std::vector<int> gtOfEstimate;    // instance index, -1 if unmatched
	std::vector<double> estimateError; // error to that instance, +inf if unmatched
	std::vector<int> estimateOfGt;    // estimate index, -1 if missed
};

// errors(e, g): pose error of estimate e against instance g; scores[e].
MatchResult matchGreedy(const std::vector<double> &scores, const Eigen::MatrixXd &errors);

} // namespace ihf
