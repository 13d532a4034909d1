// SPDX-License-Identifier: MIT
#pragma once

// Refinement's re-search as a proposal source: the view templates searched
// again at the polished best hypothesis' own translation. The
// registration's searches place each rotation by the box and by depth
// slabs, which puts the true rotation millimetres to tens of millimetres off
// where the box is off or clipped, while the polish has moved the best,
// right or wrong in rotation, onto the object. The new proposals' best are
// polished; another round follows while one improves the best
// (EstimatorConfig::researchRounds). Not in the paper.

#include <cstdint>

#include "core/estimation/proposal_source.h"

namespace ihf {

// Proposals of a re-search round that are polished.
size_t researchPolished(const EstimatorConfig &config);
// Refinement's re-search rounds: at most the requested k, whatever the
// budget's bound on the iterations; none without the view search.
int researchRounds(const EstimatorConfig &config, int requestedIterations, const ObjectModel &model);

class ResearchSource : public ProposalSource
{
public:
	bool enabled(const ProposalBox &box) const override;
	// Rounds from `best`, each only if it fits the budget with its polish;
	// returns the best found (`best` when none is better).
	Hypothesis propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis> polished) override;

	// Rounds run in the last box, and over all boxes, and those that found
	// a better pose.
	int lastRounds() const { return lastRounds_; }
	uint64_t rounds() const { return rounds_; }
	uint64_t wins() const { return wins_; }
	void forgetCounts() { rounds_ = wins_ = 0; }

private:
	// One round at `from`: its proposals, then those that are not `from`
	// itself polished; returns the round's best.
	Hypothesis round(ProposalBox &box, const Hypothesis &from);

	int lastRounds_ = 0;
	uint64_t rounds_ = 0, wins_ = 0;
};

} // namespace ihf
