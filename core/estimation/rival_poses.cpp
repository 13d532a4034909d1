// SPDX-License-Identifier: MIT
#include "core/estimation/rival_poses.h"

#include <algorithm>

namespace ihf {

float poseConfidence(float score, float margin, const ConfidenceConfig &config)
{
	if (config.fullMargin <= 0)
		return score;
	return score * std::clamp(margin / config.fullMargin, 0.0f, 1.0f);
}

void RivalPoses::add(const Pose &pose, float score)
{
	if (storage_.empty())
		return;
	if (count_ < storage_.size()) {
		storage_[count_++] = {pose, score};
		return;
	}
	auto lowest = std::min_element(storage_.begin(), storage_.end(),
				       [](const RivalPose &a, const RivalPose &b) { return a.score < b.score; });
	if (score > lowest->score)
		*lowest = {pose, score};
}

float RivalPoses::bestDistinct(const Pose &winner, std::span<const Eigen::Vector3f> vertices,
			       const Eigen::Vector3d &centre, bool symmetric, double distinctMm) const
{
	Eigen::Vector3d points[kMaxPoints];
	int n = 0;
	if (symmetric || vertices.empty()) {
		points[n++] = centre;
	} else {
		const size_t stride = (vertices.size() + kMaxPoints - 1) / kMaxPoints;
		for (size_t i = 0; i < vertices.size() && n < kMaxPoints; i += stride)
			points[n++] = vertices[i].cast<double>();
	}
	float best = 0;
	for (size_t r = 0; r < count_; ++r) {
		const RivalPose &rival = storage_[r];
		if (rival.score <= best)
			continue;
		// Mean distance of the points under the two poses.
		const Eigen::Matrix3d dR = rival.pose.R - winner.R;
		const Eigen::Vector3d dt = rival.pose.t - winner.t;
		double sum = 0;
		for (int i = 0; i < n; ++i)
			sum += (dR * points[i] + dt).norm();
		if (sum > distinctMm * n)
			best = rival.score;
	}
	return best;
}

} // namespace ihf
