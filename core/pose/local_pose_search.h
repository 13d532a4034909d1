// SPDX-License-Identifier: MIT
#pragma once

// Coarse-to-fine hill climbing of a pose score: at each level, try turning
// the object by +-step about the camera axes (about its own origin) and
// moving it by +-step along them, take the best improvement, repeat until
// none helps, then halve the steps. It widens the basin of the projective
// ICP that follows: vote modes are often 15-30 degrees off, beyond what
// ICP on same-pixel correspondences recovers (BENCHMARKS.md, issue 3).

#include <cmath>

#include <Eigen/Geometry>

#include "core/geometry/pose.h"

namespace ihf {

struct LocalSearchConfig {
	int levels = 0;                // 0: off
	float rotationStepDeg = 16.0f; // first level; halved at each level
	float translationStepMm = 8.0f;
	int maxPasses = 4;             // moves per level
};

struct LocalSearchResult {
	Pose pose;
	float score = 0;
	int evaluations = 0;
};

// score(const Pose &) -> float, higher is better.
template<typename Score>
LocalSearchResult localPoseSearch(const Pose &start, float startScore, const LocalSearchConfig &config,
				  Score &&score)
{
	LocalSearchResult r{start, startScore, 0};
	float rot = config.rotationStepDeg * static_cast<float>(M_PI / 180.0);
	float step = config.translationStepMm;
	for (int level = 0; level < config.levels; ++level, rot *= 0.5f, step *= 0.5f) {
		for (int pass = 0; pass < config.maxPasses; ++pass) {
			Pose best = r.pose;
			float bestScore = r.score;
			for (int axis = 0; axis < 3; ++axis)
				for (int sign = -1; sign <= 1; sign += 2) {
					const Eigen::Vector3d dir = Eigen::Vector3d::Unit(axis) * sign;
					Pose turned = r.pose;
					turned.R = Eigen::AngleAxisd(rot, dir).toRotationMatrix() * r.pose.R;
					Pose moved = r.pose;
					moved.t += dir * step;
					for (const Pose *p : {&turned, &moved}) {
						const float s = score(*p);
						++r.evaluations;
						if (s > bestScore) {
							bestScore = s;
							best = *p;
						}
					}
				}
			if (!(bestScore > r.score))
				break;
			r.pose = best;
			r.score = bestScore;
		}
	}
	return r;
}

} // namespace ihf
