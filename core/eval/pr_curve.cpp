// SPDX-License-Identifier: MIT
#include "core/eval/pr_curve.h"

#include <algorithm>

namespace ihf {

std::vector<PrPoint> prCurve(std::span<const ScoredOutcome> outcomes, size_t numGt,
			     double maxError)
{
	std::vector<ScoredOutcome> sorted(outcomes.begin(), outcomes.end());
	std::stable_sort(sorted.begin(), sorted.end(),
			 [](const ScoredOutcome &a, const ScoredOutcome &b) { return a.score > b.score; });

	std::vector<PrPoint> curve;
	size_t returned = 0;
	size_t correct = 0;
	for (size_t i = 0; i < sorted.size(); ++i) {
		++returned;
		if (sorted[i].error <= maxError)
			++correct;
		// Emit once all estimates sharing this score are in.
		if (i + 1 < sorted.size() && sorted[i + 1].score == sorted[i].score)
			continue;
		PrPoint p;
		p.threshold = sorted[i].score;
		p.precision = static_cast<double>(correct) / static_cast<double>(returned);
		p.recall = numGt ? static_cast<double>(correct) / static_cast<double>(numGt) : 0.0;
		const double sum = p.precision + p.recall;
		p.f1 = sum > 0 ? 2.0 * p.precision * p.recall / sum : 0.0;
		curve.push_back(p);
	}
	return curve;
}

double bestF1(std::span<const PrPoint> curve)
{
	double best = 0;
	for (const PrPoint &p : curve)
		best = std::max(best, p.f1);
	return best;
}

double recallAt(std::span<const ScoredOutcome> outcomes, size_t numGt, double maxError)
{
	if (numGt == 0)
		return 0;
	size_t correct = 0;
	for (const ScoredOutcome &o : outcomes)
		if (o.error <= maxError)
			++correct;
	return static_cast<double>(correct) / static_cast<double>(numGt);
}

} // namespace ihf
