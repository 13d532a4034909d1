// SPDX-License-Identifier: MIT
#pragma once

// What the estimator tells an observer while it works on a box: every
// scored hypothesis and the votes of every pass (debugging, the `--trace`
// of ihf estimate, iteration pictures).

#include <span>

#include <Eigen/Core>

#include "core/estimation/hypothesis_score.h"
#include "core/geometry/pose.h"
#include "core/pose/vote_modes.h"

namespace ihf {

// One scored hypothesis.
struct HypothesisEvent {
	// 0: initial registration, k: refinement k, the refinement's count
	// plus one: a proposal of a search after the refinement.
	int iteration = 0;
	const char *stage = ""; // "mode", "icp", "view", "research", "half_turn", ...
	int rank = 0;           // rank within its stage
	Pose pose;              // model -> real camera
	HypothesisScore score;
	float voteDensity = 0;
};

// The votes of one pass, before mode finding (does the forest vote for the
// true pose at all, or does mode finding lose it?).
struct VoteEvent {
	int iteration = 0;
	int pass = 0;                    // depth window of the initial registration
	Eigen::Matrix3d cropRotation;    // virtual crop camera -> real camera
	std::span<const CastVote> votes; // in the virtual crop camera
};

class EstimateObserver
{
public:
	virtual ~EstimateObserver() = default;
	virtual void onHypothesis(const HypothesisEvent &event) = 0;
	virtual void onVotes(const VoteEvent &) {}
};

} // namespace ihf
