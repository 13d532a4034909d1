// SPDX-License-Identifier: MIT
#pragma once

// The Hough voter (paper Sect. III-C, Eq. 8): a depth image becomes a cloud,
// the cloud is normalised into the unit cube, the IBS is fitted, the parts
// are extracted and described (HoCP), each part is passed down the forest
// and casts its leaves' votes, and the votes' modes are the pose hypotheses.
// Each step laps its stage on the stage timer; the peaks record how much of
// each limit the largest box used. All buffers are the workspace's.

#include <optional>
#include <span>

#include "core/estimation/box_scorer.h"
#include "core/estimation/candidate_pool.h"
#include "core/estimation/estimator_config.h"
#include "core/estimation/estimator_stats.h"
#include "core/estimation/estimator_workspace.h"
#include "core/features/unit_cube_frame.h"
#include "core/model/object_model.h"
#include "core/pose/vote_modes.h"
#include "core/runtime/stage_timer.h"

namespace ihf {

struct VoteCount {
	int parts = 0;
	int votes = 0;
};

class HoughVoter
{
public:
	HoughVoter(EstimatorWorkspace &workspace, StageTimer &timer, EstimatorPeaks &peaks)
		: workspace_(workspace), timer_(timer), peaks_(peaks)
	{
	}

	// The depth image (the box's window or a mask of it) back-projected into
	// the workspace's cloud; returns its points.
	int buildCloud(ImageView<const float> depth, const CameraIntrinsics &K, const ModelParams &params);

	// The votes of the cloud's first cloudPoints points into the
	// workspace's vote buffer. frame: the unit cube to normalise with (only
	// the points inside it take part); null: the cloud's own (Eq. 1).
	VoteCount vote(const CameraIntrinsics &K, const ObjectModel &model, const EstimatorConfig &config,
		       int cloudPoints, const UnitCubeFrame *frame);
	std::span<const CastVote> votes(int count) const
	{
		return std::span<const CastVote>(workspace_.votes().votes.data(), static_cast<size_t>(count));
	}

	// The modes of the first `count` votes, at most maxModes of them (the
	// seeds: as many as the workspace holds).
	std::span<const PoseMode> findModes(int count, const VoteModeConfig &config, size_t maxModes);

private:
	// Parts [first, last) walked down the forest, their votes appended to
	// out from its start; returns how many.
	size_t walkParts(const ObjectModel &model, int first, int last, std::span<float> hist,
			 std::span<CastVote> out) const;
	// Every part's votes into the vote buffer, spread over the pool's
	// threads; returns how many.
	size_t castVotes(const ObjectModel &model, int partCount);

	EstimatorWorkspace &workspace_;
	StageTimer &timer_;
	EstimatorPeaks &peaks_;
};

// The unit cube of the model surface a hypothesis shows (its render), as
// training normalises with the whole silhouette; nothing when it shows none.
std::optional<UnitCubeFrame> hypothesisFrame(BoxScorer &scorer, const Pose &pose);

// The modes as hypotheses of `iteration` (0: the registration): scored side
// by side, reported and kept in mode order. Returns the best.
Hypothesis scoreModes(std::span<const PoseMode> modes, int iteration, BoxScorer &scorer, CandidatePool &pool);

} // namespace ihf
