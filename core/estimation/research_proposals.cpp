// SPDX-License-Identifier: MIT
#include "core/estimation/research_proposals.h"

#include <algorithm>

#include "core/estimation/view_proposals.h"

namespace ihf {

size_t researchPolished(const EstimatorConfig &config)
{
	return std::min(viewKeep(config), static_cast<size_t>(std::max(0, config.researchPolish)));
}

int researchRounds(const EstimatorConfig &config, int requestedIterations, const ObjectModel &model)
{
	if (!(viewSearchSize(model.viewTemplates(), config.views) > 0))
		return 0;
	return std::max(0, std::min(config.researchRounds, requestedIterations));
}

bool ResearchSource::enabled(const ProposalBox &box) const
{
	return researchRounds(box.config, box.requestedIterations, box.model) > 0;
}

Hypothesis ResearchSource::propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis>)
{
	const EstimatorConfig &config = box.config;
	const int maxRounds = researchRounds(config, box.requestedIterations, box.model);
	const size_t polishN = researchPolished(config);
	Hypothesis winner = best;
	for (lastRounds_ = 0; lastRounds_ < maxRounds;) {
		// The search and its polish rounds must fit.
		if (!box.planner.researchFits(config.budgetMargin, config.icp ? box.polisher.rounds(polishN) : 0))
			break;
		++lastRounds_;
		++rounds_;
		const Hypothesis roundBest = round(box, winner);
		if (!roundBest.valid || roundBest.score.score <= winner.score.score)
			break;
		winner = roundBest;
		++wins_;
	}
	return winner;
}

// Every proposal competes; those that are not `from` itself, best first (as
// the search returns them), are polished in rounds of the pool's threads.
Hypothesis ResearchSource::round(ProposalBox &box, const Hypothesis &from)
{
	const EstimatorConfig &config = box.config;
	const size_t polishN = researchPolished(config);
	const size_t threads = static_cast<size_t>(box.polisher.threads());
	const double same = 0.05 * box.model.params().diameter;
	const int64_t start = box.planner.timer().last();
	Hypothesis found[kMaxViewKeep];
	const size_t n = searchScored(box, from.pose.t, 0.0f, "research", std::span<Hypothesis>(found, viewKeep(config)));
	box.planner.observeSearch(start);
	Hypothesis fresh[kMaxViewKeep], polished[kMaxViewKeep];
	Hypothesis best;
	size_t m = 0;
	for (size_t j = 0; j < n; ++j) {
		takeBetter(best, found[j]);
		if (m < polishN && !samePose(found[j].pose, from.pose, same))
			fresh[m++] = found[j];
	}
	for (size_t c0 = 0; config.icp && c0 < m; c0 += threads) {
		const int64_t icpStart = box.planner.timer().last();
		const size_t k = std::min(threads, m - c0);
		box.polisher.polishAll(std::span<const Hypothesis>(fresh + c0, k), std::span<Hypothesis>(polished + c0, k),
				       Stage::kIcp);
		box.planner.observePolish(icpStart);
		for (size_t c = c0; c < c0 + k; ++c) {
			if (!polished[c].valid)
				continue;
			box.pool.report(polished[c], "research_icp", static_cast<int>(c));
			takeBetter(best, polished[c]);
		}
	}
	return best;
}

} // namespace ihf
