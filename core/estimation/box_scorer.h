// SPDX-License-Identifier: MIT
#pragma once

// The scorer of one box: poses rendered and scored in the box's window
// (pose_scorer.h) on the slot of the thread that asks, so that the pool's
// threads score side by side; and what a pose shows of the model (its
// rendered surface back-projected), which the refinement's unit cube and
// the half-turns' alignment are taken from.

#include <optional>
#include <span>

#include <Eigen/Core>

#include "core/estimation/estimator_workspace.h"
#include "core/estimation/pose_scorer.h"

namespace ihf {

class BoxScorer
{
public:
	BoxScorer(EstimatorWorkspace &workspace, const ScoreWindow &window, const ObjectModel &model)
		: workspace_(workspace), window_(window), model_(model)
	{
	}

	const ScoreWindow &window() const { return window_; }
	const CameraIntrinsics &intrinsics() const { return window_.K; }
	const ObjectModel &model() const { return model_; }

	// The pose's score, rendered on `slot` (0: the caller's thread).
	HypothesisScore score(const Pose &pose, int slot = 0);
	// Scores poses[i] into scores[i], spread over the pool's threads; a pose
	// behind the camera gets a zero score.
	void scoreAll(std::span<const Pose> poses, std::span<HypothesisScore> scores);
	// The pose rendered into the slot's render buffer; false if the render
	// failed.
	bool render(const Pose &pose, int slot = 0);

	// Calls f with every pixel the pose covers, back-projected (camera
	// frame); false if the render failed.
	template<typename F>
	bool forEachShownPoint(const Pose &pose, F &&f, int slot = 0);
	// The centroid (camera frame) of the model surface the pose shows.
	std::optional<Eigen::Vector3d> shownCentroid(const Pose &pose, int slot = 0);

private:
	EstimatorWorkspace &workspace_;
	ScoreWindow window_;
	const ObjectModel &model_;
};

template<typename F>
bool BoxScorer::forEachShownPoint(const Pose &pose, F &&f, int slot)
{
	if (!render(pose, slot))
		return false;
	const ImageView<float> view = workspace_.slot(slot).render;
	const CameraIntrinsics &K = window_.K;
	for (int y = 0; y < view.height; ++y)
		for (int x = 0; x < view.width; ++x) {
			const float z = view.at(x, y);
			if (z > 0)
				f(K.backProject(x, y, z));
		}
	return true;
}

} // namespace ihf
