// SPDX-License-Identifier: MIT
#pragma once

// The polisher of one box: a hypothesis polished by ICP on the box's window
// cut to its own depth range (Eq. 10's mask: the occluder in front and the
// table behind do not pull), then scored (icp_polisher.h). On one thread the
// mask and cloud are the box's own and the stage timer sees the cloud
// apart; on several, each polish runs on its thread's slot and the caller
// charges the round (the clock is read by the calling thread alone).

#include <span>

#include "core/estimation/box_scorer.h"
#include "core/estimation/candidate_pool.h"
#include "core/estimation/estimator_config.h"
#include "core/estimation/estimator_workspace.h"
#include "core/estimation/hough_voter.h"
#include "core/runtime/stage_timer.h"

namespace ihf {

class HypothesisPolisher
{
public:
	HypothesisPolisher(EstimatorWorkspace &workspace, HoughVoter &voter, StageTimer &timer, BoxScorer &scorer,
			   const EstimatorConfig &config)
		: workspace_(workspace), voter_(voter), timer_(timer), scorer_(scorer), config_(config)
	{
	}

	// h polished on `slot`: the polished hypothesis (h's origin), or an
	// invalid one when ICP could not run. On one thread the time before it
	// is charged to `stage`, the ICP and its score to Stage::kIcp.
	Hypothesis polish(const Hypothesis &h, Stage stage, int slot, const IcpConfig &icp);
	// in[i] polished into out[i] with the configured ICP, side by side on
	// the pool's threads.
	void polishAll(std::span<const Hypothesis> in, std::span<Hypothesis> out, Stage stage);
	// The rounds of the pool's threads that polish this many hypotheses.
	int rounds(size_t polishes) const;
	int threads() const { return workspace_.threads(); }

	// The working mask cut to h's depth range, widened by psi1 and psi2
	// (Eq. 10): what the next refinement iteration votes on.
	void maskToHypothesis(const HypothesisScore &h);

private:
	// On one thread: the box's own mask and cloud, the stages timed.
	Hypothesis polishHere(const Hypothesis &h, Stage stage, const IcpConfig &icp);
	// On a pool thread's slot, untimed.
	Hypothesis polishOnSlot(const Hypothesis &h, int slot, const IcpConfig &icp);

	EstimatorWorkspace &workspace_;
	HoughVoter &voter_;
	StageTimer &timer_;
	BoxScorer &scorer_;
	const EstimatorConfig &config_;
};

} // namespace ihf
