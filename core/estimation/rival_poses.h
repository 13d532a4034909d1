// SPDX-License-Identifier: MIT
#pragma once

// The confidence of a box's pose (not in the paper, whose Sect. IV only
// needs one to sweep precision against recall). The winner's score alone
// ranks a coin toss between two different poses, say a duck and the same
// duck turned half round, which fit the depth equally well, as high as a
// clear win; the gap to the best pose that is not the winner says how sure
// the choice was. Every scored hypothesis of a box is offered here; at the
// end the margin is the winner's score less the best score of a rival that
// lies more than distinctShare diameters from it, measured as the
// evaluation measures a pose error (the mean distance of model points).
// Symmetric objects are compared by their centre only, since a turn by a
// symmetry is not a different pose.
// Syn200/syn77/syn99, nine forest x benchmark runs: mean F1 0.867 with the
// confidence = score min(1, margin / 0.1) against 0.847 with the score alone
// (BENCHMARKS.md).

#include <span>

#include <Eigen/Core>

#include "core/estimation/pose_distance.h"
#include "core/geometry/pose.h"

namespace ihf {

struct ConfidenceConfig {
	float distinctShare = 0.1f; // a rival counts when its points lie this far, in diameters
	float fullMargin = 0.1f;    // a margin this large keeps the whole score; 0: confidence = score
};

// score, scaled down when the margin over the best distinct rival is less
// than config.fullMargin.
float poseConfidence(float score, float margin, const ConfidenceConfig &config);

struct RivalPose {
	Pose pose;
	float score = 0;
};

class RivalPoses
{
public:
	RivalPoses() = default;
	explicit RivalPoses(std::span<RivalPose> storage) : storage_(storage) {}

	void clear() { count_ = 0; }
	size_t size() const { return count_; }

	// Keeps the highest-scoring poses once the storage is full.
	void add(const Pose &pose, float score);

	// The best score of a stored pose whose sample points lie on average
	// more than distinctMm from winner's (or whose `centre` does, when
	// symmetric); 0 when there is none. vertices: the model's, sampled
	// evenly up to kPoseDistancePoints (pose_distance.h).
	float bestDistinct(const Pose &winner, std::span<const Eigen::Vector3f> vertices, const Eigen::Vector3d &centre,
			   bool symmetric, double distinctMm) const;

	// The highest-scoring stored poses, best first, each lying on average
	// more than distinctMm from winner's and from those before it, into
	// out; returns how many (at most out.size()).
	size_t bestDistinctPoses(const Pose &winner, std::span<const Eigen::Vector3f> vertices, double distinctMm,
				 std::span<RivalPose> out) const;

private:
	std::span<RivalPose> storage_;
	size_t count_ = 0;
};

} // namespace ihf
