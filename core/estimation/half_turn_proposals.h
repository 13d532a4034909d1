// SPDX-License-Identifier: MIT
#pragma once

// The half-turns as a proposal source (half_turns.h): the best distinct
// polished hypotheses turned by 180 deg about axes through the model's box
// centre (a wrong pose that fits the depth is often the right one turned
// half round), the turns scored and the best few of each polished. Each
// source hypothesis runs under the budget. Not in the paper.

#include "core/estimation/proposal_source.h"

namespace ihf {

class HalfTurnSource : public ProposalSource
{
public:
	bool enabled(const ProposalBox &box) const override;
	// Turns of `best` and of the best polished hypotheses unlike it;
	// returns the best found (`best` when none scores higher).
	Hypothesis propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis> polished) override;

private:
	// One source's turns, every one rendered and scored; the best keepN
	// into top.
	static void scoreTurns(ProposalBox &box, const Hypothesis &source, FixedListBase<Hypothesis> &top);
	// One source's turns screened on the view templates: every turn placed
	// by its template's centroid and scored sparsely, the `screen` best
	// rendered and scored; the best keepN into top.
	static void screenTurns(ProposalBox &box, const Hypothesis &source, FixedListBase<Hypothesis> &top);
	// The kept turns polished, each reported (ranks from rankBase); found
	// takes any better one.
	static void polishTurns(ProposalBox &box, std::span<const Hypothesis> top, int rankBase, Hypothesis &found);
};

} // namespace ihf
