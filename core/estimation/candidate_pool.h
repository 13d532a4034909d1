// SPDX-License-Identifier: MIT
#pragma once

// The hypotheses of one box and where they came from. Every scored
// hypothesis is reported here: it becomes a rival for the confidence
// (rival_poses.h) and an event for the observer. The distinct best ones are
// kept, ranked by score, twice: all of them, and those of the registration
// and the searches alone (without the refinement iterations' modes), so that
// refinement never crowds out what the registration alone would have
// polished. The kept ones are what the searches centre on and the polish
// starts from.

#include <span>

#include <Eigen/Core>

#include "core/common/fixed_list.h"
#include "core/estimation/estimate_observer.h"
#include "core/estimation/hypothesis_score.h"
#include "core/estimation/rival_poses.h"
#include "core/geometry/pose.h"

namespace ihf {

// Where a hypothesis came from: a vote mode of the initial registration or
// of a refinement iteration, or a proposal of a search after the votes
// (view templates, re-search, half-turns). A polish keeps its start's origin.
enum class HypothesisOrigin {
	kRegistration,
	kRefinement,
	kProposal,
};

struct Hypothesis {
	Pose pose; // model -> virtual crop camera
	HypothesisScore score;
	HypothesisOrigin origin = HypothesisOrigin::kRegistration;
	int iteration = 0; // the refinement iteration (1...k) of a kRefinement mode
	bool valid = false;
};

// Two hypotheses are one when their translations lie within
// sameTranslationMm and their rotations within 10 deg.
bool samePose(const Pose &a, const Pose &b, double sameTranslationMm);

// h becomes candidate when candidate is valid and scores higher (or h is
// invalid); h stays on a tie. Returns whether candidate won.
bool takeBetter(Hypothesis &h, const Hypothesis &candidate);

// Inserts h into a list of hypotheses ranked best first (insertRanked()).
bool insertByScore(FixedListBase<Hypothesis> &ranked, const Hypothesis &h);

class CandidatePool
{
public:
	CandidatePool() = default;
	CandidatePool(const CandidatePool &) = delete;
	CandidatePool &operator=(const CandidatePool &) = delete;

	// The storage of the kept lists (their capacity: EstimatorLimits::
	// maxCandidates each) and of the rivals.
	void attach(std::span<Hypothesis> kept, std::span<Hypothesis> registrationKept,
		    std::span<RivalPose> rivals);
	void setObserver(EstimateObserver *observer) { observer_ = observer; }
	EstimateObserver *observer() const { return observer_; }

	// A box starts: nothing kept, no rivals. Its hypotheses are reported in
	// the real camera (cropRotation: virtual crop camera -> real camera);
	// near duplicates lie within 0.05 of the model's diameter; the box runs
	// `iterations` refinement iterations.
	void beginBox(const Eigen::Matrix3d &cropRotation, double diameter, int iterations);

	// Keeps h among the best distinct hypotheses (and, unless it is a
	// refinement iteration's, among the registration's); a near duplicate of
	// a kept one replaces it only if it scores higher.
	void keep(const Hypothesis &h);
	// Every scored hypothesis passes here: a rival for the confidence, and
	// an event for the observer under `stage` and `rank`.
	void report(const Hypothesis &h, const char *stage, int rank, float voteDensity = 0);
	// A comparison of the best with a rival, for the observer (event.rival
	// in the crop's camera; turned to the real camera here). Not a
	// hypothesis: it joins no ranking.
	void reportComparison(ComparisonEvent event) const;
	// The votes of a pass, for the observer.
	void reportVotes(int iteration, int pass, std::span<const CastVote> votes) const;

	bool empty() const { return kept_.empty(); }
	const Hypothesis &best() const { return kept_.front(); }
	std::span<const Hypothesis> kept() const { return kept_.items(); }

	// The translations of the kept hypotheses, best first, each at least
	// apartMm from those before it, into out; returns how many.
	size_t distinctCentres(double apartMm, std::span<Eigen::Vector3d> out) const;

	// What the polish starts from, into out: the `wanted` best distinct
	// hypotheses; after a refinement (refinementBest valid) also the
	// registration's best distinct ones (withRegistration) and the forest's
	// own bests (withForestBests) where those are not among them.
	struct PolishChoice {
		int wanted = 0;
		bool withRegistration = true;
		bool withForestBests = true;
	};
	void polishCandidates(const PolishChoice &choice, const Hypothesis &registrationBest,
			      const Hypothesis &refinementBest, FixedListBase<Hypothesis> &out) const;

	// The iteration an observer and PoseEstimate see for h (HypothesisEvent).
	int reportedIteration(const Hypothesis &h) const;

	// The best-scoring reported poses distinct from winner and from each
	// other (RivalPoses::bestDistinctPoses()).
	size_t bestDistinctRivals(const Pose &winner, std::span<const Eigen::Vector3f> vertices, double distinctMm,
				  std::span<RivalPose> out) const
	{
		return rivals_.bestDistinctPoses(winner, vertices, distinctMm, out);
	}

	// The best score of a rival distinct from winner (RivalPoses::bestDistinct()).
	float bestDistinctRival(const Pose &winner, std::span<const Eigen::Vector3f> vertices,
				const Eigen::Vector3d &centre, bool symmetric, double distinctMm) const
	{
		return rivals_.bestDistinct(winner, vertices, centre, symmetric, distinctMm);
	}

private:
	// Keeps h in one of the ranked lists.
	void keepIn(FixedListBase<Hypothesis> &kept, const Hypothesis &h) const;
	// A pose in the crop's camera as the real camera sees it (observer events).
	Pose inRealCamera(const Pose &crop) const;

	FixedListBase<Hypothesis> kept_;
	FixedListBase<Hypothesis> registrationKept_;
	RivalPoses rivals_;
	EstimateObserver *observer_ = nullptr;
	Eigen::Matrix3d cropRotation_ = Eigen::Matrix3d::Identity();
	float sameMm_ = 0;
	double diameter_ = 0;
	int iterations_ = 0;
};

} // namespace ihf
