// SPDX-License-Identifier: MIT
#pragma once

// Scoring of pose estimates against ground truth, as in Sect. IV of the
// paper and its NOTES §7 (pure: no files; see eval_dataset.h for those).
//
// Semantics:
// - Metric: objects whose models_info.json entry lists symmetries
//   (symmetries_discrete or symmetries_continuous) use ADI, the others ADD
//   (pose_error.h), over every model vertex. Phi is the model diameter from
//   models_info.json.
// - Ground truths: every instance handed in (the dataset layer passes each
//   scene_gt.json instance of an evaluated object in every image of the
//   split, optionally only images/objects with a target box).
// - Matching: per (scene, image, object), estimates in decreasing score take
//   the unmatched instance with the smallest error (matching.h), each
//   instance at most once; the rest are false positives. An instance without
//   an estimate is a miss: it stays in recall's denominator.
// - For each z in 0.05, 0.06, ..., 0.15 an estimate is correct iff its error
//   <= z * Phi; sweeping the confidence threshold over every distinct score,
//   precision = correct returned / returned, recall = correct returned /
//   #GT, and F1(z) = the best 2PR/(P+R) over thresholds (0 if nothing is
//   returned) (pr_curve.h). meanF1 averages F1 over the z values.
// - recall at 0.1: the ADD(-S)-0.1d score, the fraction of instances whose
//   matched estimate has error <= 0.1 Phi, whatever its score.
// - Time: median over distinct images (scene, image) of the results' `time`
//   column, negative values (unknown) left out; if the rows of one image
//   disagree the largest is used. -1 when no image has a time.
// - Visible surface (when the caller hands in e_VSD, visible_surface.h):
//   for each tau the estimates of a (scene, image, object) are matched
//   again, greedily on e_VSD, and one is correct at (tau, theta) iff its
//   e_VSD < theta; AR_VSD = the recall averaged over the (tau, theta)
//   pairs, whatever the scores, as BOP reports it.
// - Overall: the plain mean over objects of F1(z), mean F1, recall and
//   AR_VSD; counts are summed and the median time is over all distinct
//   images.

#include <map>
#include <vector>

#include "core/dataset/bop_types.h"
#include "core/eval/pose_error.h"
#include "core/eval/pr_curve.h"

namespace ihf {

// 0.05, 0.06, ..., 0.15.
std::vector<double> defaultZValues();
inline constexpr double kRecallZ = 0.1;

struct EvalGt {
	int sceneId = 0;
	int imId = 0;
	int objId = 0;
	Pose pose;
};

struct EvalObject {
	double diameter = 0; // Phi, > 0
	const ObjectPoseError *error = nullptr; // must outlive the call
};

struct ObjectEvalResult {
	int objId = 0;
	PoseMetric metric = PoseMetric::kAdd;
	double diameter = 0;
	size_t numGt = 0;
	size_t numEstimates = 0;
	size_t numMatched = 0;
	std::vector<double> f1; // per z value
	double meanF1 = 0;
	double recall = 0; // at kRecallZ
	double medianTime = -1; // seconds, -1 if unknown
	double arVsd = -1; // -1 when not scored
	std::vector<std::vector<PrPoint>> curves; // per z value
};

// One estimate's pose error against the ground truth it was matched to.
struct EstimateOutcome {
	int sceneId = 0;
	int imId = 0;
	int objId = 0;
	double score = 0;
	bool matched = false;
	double error = 0; // mm (ADD or ADI), meaningful when matched
	// Share of the (tau, theta) pairs at which it is correct by the visible
	// surface; -1 when not scored.
	double vsdShare = -1;
};

// e_VSD of estimates against instances, for each of `tauShares` (of the
// diameter), keyed by (estimate index, instance index) into the vectors
// handed to evaluatePoses(). Every pair of the same scene, image and object
// must be there. Filled by the dataset layer, which has the depth images.
struct VsdErrors {
	std::vector<double> tauShares;
	std::vector<double> thetas;
	std::map<std::pair<size_t, size_t>, std::vector<double>> errors;
};

struct EvalReport {
	std::vector<double> zValues;
	std::vector<ObjectEvalResult> objects; // ascending object id
	// Means over objects.
	std::vector<double> meanF1PerZ;
	double meanF1 = 0;
	double meanRecall = 0;
	double medianTime = -1;
	double meanArVsd = -1; // -1 when not scored
	size_t numGt = 0;
	size_t numEstimates = 0;
	size_t numIgnored = 0; // estimates outside the evaluated set (dataset layer)
	std::vector<EstimateOutcome> estimates; // every evaluated estimate
};

// Scores `estimates` against `gts` for every object in `objects` (also those
// without any ground truth or estimate). Rows of other objects are ignored.
// Scores must be finite (the dataset layer checks). With vsd, AR_VSD too.
EvalReport evaluatePoses(const std::map<int, EvalObject> &objects,
			 const std::vector<EvalGt> &gts,
			 const std::vector<ResultRow> &estimates,
			 const std::vector<double> &zValues = defaultZValues(),
			 const VsdErrors *vsd = nullptr);

// Median of the non-negative values, -1 if there are none.
double medianKnown(std::vector<double> values);

} // namespace ihf
