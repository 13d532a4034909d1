// SPDX-License-Identifier: MIT
#include "core/estimation/box_scorer.h"

namespace ihf {

HypothesisScore BoxScorer::score(const Pose &pose, int slot)
{
	const WorkSlot s = workspace_.slot(slot);
	return scoreInWindow(window_, *s.renderer, s.render, model_, pose);
}

void BoxScorer::scoreAll(std::span<const Pose> poses, std::span<HypothesisScore> scores)
{
	workspace_.workers().run(static_cast<int>(poses.size()), [&](int i, int thread) {
		const Pose &pose = poses[static_cast<size_t>(i)];
		// Behind the camera: nothing to render (callers skip those).
		scores[static_cast<size_t>(i)] = pose.t.z() > 0 ? score(pose, thread) : HypothesisScore{};
	});
}

bool BoxScorer::render(const Pose &pose, int slot)
{
	const WorkSlot s = workspace_.slot(slot);
	return renderModel(*s.renderer, s.render, model_, pose, window_.K);
}

// A half-turn about the model's centre moves the surface a pose shows when
// the object is not symmetric about it (a can's body beside its handle, by
// tens of millimetres); moving the turn by the difference of the centroids
// puts it back where the hypothesis saw it.
std::optional<Eigen::Vector3d> BoxScorer::shownCentroid(const Pose &pose, int slot)
{
	Eigen::Vector3d sum = Eigen::Vector3d::Zero();
	int n = 0;
	const bool rendered = forEachShownPoint(
		pose,
		[&](const Eigen::Vector3d &p) {
			sum += p;
			++n;
		},
		slot);
	if (!rendered || n == 0)
		return std::nullopt;
	return sum / n;
}

} // namespace ihf
