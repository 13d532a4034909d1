// SPDX-License-Identifier: MIT
#include "core/estimation/rival_poses.h"

#include <algorithm>

#include "core/estimation/pose_distance.h"

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
	Eigen::Vector3d points[kPoseDistancePoints];
	int n = 0;
	if (symmetric || vertices.empty())
		points[n++] = centre;
	else
		n = sampleModelPoints(vertices, points);
	const std::span<const Eigen::Vector3d> sampled(points, static_cast<size_t>(n));
	float best = 0;
	for (size_t r = 0; r < count_; ++r) {
		const RivalPose &rival = storage_[r];
		if (rival.score > best && meanPointDistance(rival.pose, winner, sampled) > distinctMm)
			best = rival.score;
	}
	return best;
}

size_t RivalPoses::bestDistinctPoses(const Pose &winner, std::span<const Eigen::Vector3f> vertices,
				     double distinctMm, std::span<RivalPose> out) const
{
	Eigen::Vector3d points[kPoseDistancePoints];
	const int n = sampleModelPoints(vertices, points);
	if (n == 0)
		return 0;
	const std::span<const Eigen::Vector3d> sampled(points, static_cast<size_t>(n));
	// Bounds on the mean distance that settle most pairs without the
	// points: it is at least the distance of the points' mean and at most
	// |dt| + |dR| times the points' mean norm. The winner's many near copies
	// score highest and are measured again at every pick.
	Eigen::Vector3d mean = Eigen::Vector3d::Zero();
	double meanNorm = 0;
	for (int i = 0; i < n; ++i) {
		mean += points[i];
		meanNorm += points[i].norm();
	}
	mean /= n;
	meanNorm /= n;
	auto distinct = [&](const Pose &a, const Pose &b) {
		const Eigen::Matrix3d dR = a.R - b.R;
		const Eigen::Vector3d dt = a.t - b.t;
		if ((dR * mean + dt).norm() > distinctMm * (1 + 1e-9))
			return true;
		if (dt.norm() + dR.norm() * meanNorm < distinctMm * (1 - 1e-9))
			return false;
		return meanPointDistance(a, b, sampled) > distinctMm;
	};
	// Each time the best-scoring stored pose apart from the winner and from
	// those taken (a taken one is not apart from itself).
	size_t taken = 0;
	while (taken < out.size()) {
		const RivalPose *next = nullptr;
		for (size_t r = 0; r < count_; ++r) {
			const RivalPose &rival = storage_[r];
			if ((next && rival.score <= next->score) || !distinct(rival.pose, winner))
				continue;
			bool alone = true;
			for (size_t j = 0; j < taken && alone; ++j)
				alone = distinct(rival.pose, out[j].pose);
			if (alone)
				next = &rival;
		}
		if (!next)
			break;
		out[taken++] = *next;
	}
	return taken;
}

} // namespace ihf
