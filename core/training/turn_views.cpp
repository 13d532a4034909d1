// SPDX-License-Identifier: MIT
#include "core/training/turn_views.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/pose/half_turns.h"
#include "core/training/view_sampler.h"

namespace ihf {

TurnViews::TurnViews(const Mesh &mesh, const TurnViewsConfig &config)
	: mesh_(mesh), config_(config), renderer_(mesh.vertices.size())
{
	const double diameter = std::max(meshDiameter(mesh), 1e-3);
	// The camera three diameters from the box centre, looking at it: every
	// turn about an axis through the box keeps the object in the image.
	const double distance = 3 * diameter;
	tolerance_ = static_cast<float>(config.toleranceShare * diameter);
	const int size = std::max(config.imageSize, 8);
	K_.fx = K_.fy = config.pixelsAcross * distance / diameter;
	K_.cx = K_.cy = 0.5 * (size - 1);
	K_.width = K_.height = size;
	const Eigen::Vector3d centre = boundingBox(mesh).centre().cast<double>();
	ViewSamplerConfig views;
	views.viewpoints = std::max(config.viewpoints, 1);
	views.inplaneSteps = 1;
	views.minDistance = views.maxDistance = distance;
	for (const TrainingView &v : sampleTrainingViews(views))
		poses_.push_back({v.pose.R, v.pose.t - v.pose.R * centre});
	const size_t pixels = static_cast<size_t>(size) * static_cast<size_t>(size);
	plain_.assign(pixels * poses_.size(), 0.0f);
	turned_.assign(pixels, 0.0f);
	for (size_t i = 0; i < poses_.size(); ++i) {
		ImageView<float> depth(plain_.data() + i * pixels, size, size);
		(void)renderer_.render(mesh_, poses_[i], K_, depth);
	}
}

TurnLook TurnViews::compare(const Eigen::Vector3d &axis, const Eigen::Vector3d &point, double deg, double giveUpAbove)
{
	const double views = static_cast<double>(poses_.size());
	const Eigen::Matrix3d turn = Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, axis.normalized()).toRotationMatrix();
	const size_t pixels = turned_.size();
	double shareSum = 0;
	int alike = 0;
	for (size_t i = 0; i < poses_.size(); ++i) {
		const Pose turned = turnedAbout(poses_[i], turn, point);
		std::fill(turned_.begin(), turned_.end(), 0.0f);
		ImageView<float> depth(turned_.data(), K_.width, K_.height);
		(void)renderer_.render(mesh_, turned, K_, depth);
		const float *a = plain_.data() + i * pixels;
		size_t drawn = 0, differing = 0;
		for (size_t k = 0; k < pixels; ++k) {
			const bool da = a[k] > 0, db = turned_[k] > 0;
			if (!da && !db)
				continue;
			++drawn;
			if (da != db || std::abs(a[k] - turned_[k]) > tolerance_)
				++differing;
		}
		const double share = drawn ? static_cast<double>(differing) / static_cast<double>(drawn) : 0.0;
		shareSum += share;
		alike += share <= config_.alikeShare;
		if (shareSum / views > giveUpAbove)
			return {shareSum / views, 0.0};
	}
	TurnLook look;
	if (!poses_.empty()) {
		look.meanShare = shareSum / views;
		look.alikeViews = static_cast<double>(alike) / views;
	}
	return look;
}

} // namespace ihf
