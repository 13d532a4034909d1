// SPDX-License-Identifier: MIT
#pragma once

// What the estimator tells an observer while it works on a box: every
// scored hypothesis, the votes of every pass and every comparison of the
// best with a rival on the pixels where they differ (debugging, the
// `--trace` of ihf estimate, iteration pictures).

#include <span>

#include <Eigen/Core>

#include "core/estimation/hypothesis_score.h"
#include "core/estimation/part_evidence.h"
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

// The best compared with one rival on the pixels where their renders
// differ (symmetry_rivals.h): a turn of the best about a near-symmetry axis,
// or a close rival. What decided whether the best stays, and whether it is
// flagged ambiguous.
struct ComparisonEvent {
	const char *kind = "";   // "turn", "end_over_end" (a body of revolution set end over end; no verdict)
				 // or "close_rival"
	int round = 0;           // the turns' comparison round (0 for close rivals)
	int rank = 0;            // the rival's place in its round
	Pose rival;              // model -> real camera
	Eigen::Vector3d axis = Eigen::Vector3d::Zero(); // a turn's axis, model frame
	bool distinct = false;   // far enough from the best to count in the verdict
	bool reported = false;   // a turn the estimator itself reported (it may win; no verdict)
	bool polished = false;   // the rival was polished before the comparison it kept
	double score = -1;       // the polished rival's score (-1 when not polished)
	PartEvidence evidence;   // A: the best, B: the rival
	int minPixels = 0;       // the lead in pixels a verdict needed at least
};

class EstimateObserver
{
public:
	virtual ~EstimateObserver() = default;
	virtual void onHypothesis(const HypothesisEvent &event) = 0;
	virtual void onVotes(const VoteEvent &) {}
	virtual void onComparison(const ComparisonEvent &) {}
};

} // namespace ihf
