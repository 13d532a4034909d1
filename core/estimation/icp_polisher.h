// SPDX-License-Identifier: MIT
#pragma once

// The ICP polisher that detection (PoseEstimator) and tracking share: the
// observed window cut to a hypothesis' depth range (Eq. 10's mask, so that
// the occluder in front and the table behind do not pull), back-projected
// with normals, projective ICP from the hypothesis (icp_refiner.h), and the
// polished pose scored as every hypothesis is (pose_scorer.h).

#include <span>

#include "core/estimation/icp_refiner.h"
#include "core/estimation/pose_scorer.h"
#include "core/features/cloud_point.h"

namespace ihf {

// Caller-owned scratch of one polish, each at least the window's pixels.
struct PolishBuffers {
	std::span<float> mask;
	std::span<CloudPoint> cloud;
	DepthRenderer *renderer = nullptr;
	ImageView<float> render; // the window's size
};

struct PolishResult {
	Pose pose;
	HypothesisScore score;
	IcpResult icp;
	bool valid = false; // ICP ran (enough correspondences for an update)
};

// observed cut to (nearMm, farMm) into out (the window's pixels, row-major).
void cutToDepthRange(ImageView<const float> observed, float nearMm, float farMm, std::span<float> out);

// ICP from `start` on the given cloud, then the score.
PolishResult polishFromCloud(const ScoreWindow &window, const ObjectModel &model, const Pose &start,
			     std::span<const CloudPoint> cloud, const IcpConfig &icp, DepthRenderer &renderer,
			     ImageView<float> render);

// The window cut to (nearMm, farMm), its cloud, then polishFromCloud().
PolishResult polishInWindow(const ScoreWindow &window, const ObjectModel &model, const Pose &start, float nearMm,
			    float farMm, const IcpConfig &icp, const PolishBuffers &buffers);

} // namespace ihf
