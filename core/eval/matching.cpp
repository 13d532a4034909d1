// SPDX-License-Identifier: MIT
#include "core/eval/matching.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <numeric>

namespace ihf {

MatchResult matchGreedy(const std::vector<double> &scores, const Eigen::MatrixXd &errors)
{
	const size_t numEst = scores.size();
	const size_t numGt = static_cast<size_t>(errors.cols());
	assert(static_cast<size_t>(errors.rows()) == numEst);

	MatchResult match;
	match.gtOfEstimate.assign(numEst, -1);
	match.estimateError.assign(numEst, std::numeric_limits<double>::infinity());
	match.estimateOfGt.assign(numGt, -1);

	std::vector<size_t> order(numEst);
	std::iota(order.begin(), order.end(), 0);
	std::stable_sort(order.begin(), order.end(),
			 [&](size_t a, size_t b) { return scores[a] > scores[b]; });

	for (size_t e : order) {
		int best = -1;
		double bestError = std::numeric_limits<double>::infinity();
		for (size_t g = 0; g < numGt; ++g) {
			if (match.estimateOfGt[g] >= 0)
				continue;
			const double err = errors(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(g));
			// `best < 0` admits an instance even when the error is
			// infinite or NaN: it is still this estimate's instance.
			if (best < 0 || err < bestError) {
				best = static_cast<int>(g);
				bestError = err;
			}
		}
		if (best < 0)
			continue;
		match.gtOfEstimate[e] = best;
		match.estimateError[e] = bestError;
		match.estimateOfGt[static_cast<size_t>(best)] = static_cast<int>(e);
	}
	return match;
}

} // namespace ihf
