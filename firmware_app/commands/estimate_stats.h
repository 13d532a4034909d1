// SPDX-License-Identifier: MIT
#pragma once

// Reports of `ihf estimate` about the inference path: per-stage times,
// budget bookkeeping, arena use and how much of each limit was needed.

#include <cstdio>
#include <string>
#include <vector>

#include "core/estimation/estimator_stats.h"
#include "core/estimation/pose_estimator.h"

namespace ihf::app {

// A box whose pose the depth could not tell from a turn of it
// (PoseEstimate::ambiguous).
struct AmbiguousPose {
	int sceneId = 0;
	int imId = 0;
	int objId = 0;
	Eigen::Vector3d axis = Eigen::Vector3d::Zero(); // camera frame
};

struct EstimateRunSummary {
	EstimatorStats stats;
	EstimatorLimits limits;
	float frameBudgetMs = 0;
	std::vector<double> boxSeconds; // wall time of each estimate() call
	// What the boxes were taken as ("amodal" or "modal") and the score's
	// weights that follow from it.
	const char *boxKind = "amodal";
	ScoreConfig score;
	std::vector<AmbiguousPose> ambiguous;
};

void printEstimateStats(std::FILE *out, const EstimateRunSummary &summary);
std::string estimateStatsJson(const EstimateRunSummary &summary);

// Value at fraction p (0..1) of the sorted samples (nearest rank).
double percentile(std::vector<double> values, double p);

} // namespace ihf::app
