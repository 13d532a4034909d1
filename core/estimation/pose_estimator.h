// SPDX-License-Identifier: MIT
#pragma once

// IHF inference for one object in one given box (paper Sect. III-C):
//  1. the box becomes a virtual on-axis crop (virtual_crop.h);
//  2. initial registration (Eq. 8): normalise (s_0 = 1), fit the IBS,
//     extract the coarsest parts, pass them down the forest, and take the
//     vote modes; each mode is scored by rendering it (hypothesis_score.h);
//  3. iterative refinement (Eq. 10-13), k times: keep only the crop pixels
//     inside the best hypothesis' depth range [gamma psi1, beta psi2],
//     renormalise (the object grows in the unit cube, so variable-size parts
//     get finer), re-fit, vote again; the best-scoring hypothesis so far is
//     kept;
//  4. optionally a projective ICP polish (icp_refiner.h) of the few best
//     distinct hypotheses of all iterations; the best score wins.
// Hypotheses are scored by depth consistency with the crop and agreement
// with the given box (hypothesis_score.h).
// All buffers are sized at construction from EstimatorLimits; estimate()
// does not allocate.

#include <span>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/estimation/depth_windows.h"
#include "core/estimation/hypothesis_score.h"
#include "core/estimation/icp_refiner.h"
#include "core/features/cloud_point.h"
#include "core/features/part_extractor.h"
#include "core/features/unit_cube_frame.h"
#include "core/ibs/ibs_fitter.h"
#include "core/model/object_model.h"
#include "core/pose/vote_modes.h"
#include "core/render/depth_renderer.h"

namespace ihf {

struct EstimatorConfig {
	int iterations = 5; // k: refinement iterations after the initial registration
	float psi1 = 0.97f; // Eq. 10 scaling of the hypothesis' nearest depth
	float psi2 = 1.03f; // and of its farthest
	// Initial registration on the densest depth slabs of the box
	// (depth_windows.h), each depthWindowWidth diameters thick; 0 votes on
	// the whole box as the paper does.
	int depthWindows = 2;
	float depthWindowWidth = 1.0f;
	int maxHypotheses = 6; // translation modes scored per iteration
	int rotationModes = 3; // rotation modes per translation mode
	float translationBandwidth = 0.06f; // of the object diameter
	float rotationBandwidthDeg = 15.0f;
	int partStride = 0; // 0: the model's training stride
	bool icp = true;
	int icpCandidates = 8; // distinct best hypotheses polished by ICP
	IcpConfig icpConfig;
	ScoreConfig score;
	int minValidPixels = 60;
	// Refinement normalises with the unit cube of the whole rendered
	// hypothesis rather than of the (occluded) masked cloud, as training
	// normalises with the whole silhouette; false: the paper's Eq. 1 on
	// the masked cloud.
	bool hypothesisCube = true;
};

struct EstimatorLimits {
	int maxWindowPixels = 200 * 200;
	int maxParts = 3000;
	int maxPartControlPoints = 256;
	int maxVotes = 3000 * 3 * 16;
	int maxActive = 120000;
	int maxIbsPoints = 4000;
	int maxIbsN = 100;
	size_t maxMeshVertices = 50000;
	int maxModes = 32;      // vote modes per iteration (translation x rotation)
	int maxCandidates = 16; // distinct hypotheses kept over the iterations
};

// One scored hypothesis, reported to an EstimateObserver (debugging, the
// `--trace` of ihf estimate, iteration pictures).
struct HypothesisEvent {
	int iteration = 0;   // 0: initial registration, k: refinement k
	const char *stage = ""; // "mode", "icp", "given"
	int rank = 0;        // mode rank within the iteration
	Pose pose;           // model -> real camera
	HypothesisScore score;
	float voteDensity = 0;
};

class EstimateObserver
{
public:
	virtual ~EstimateObserver() = default;
	virtual void onHypothesis(const HypothesisEvent &event) = 0;
};

struct PoseEstimate {
	bool found = false;
	const char *reason = ""; // why no pose, when !found
	Pose pose;               // model -> real camera
	float confidence = 0;
	int iterationsDone = 0;
	int bestIteration = -1;
	int parts = 0;  // of the last iteration
	int votes = 0;
	bool icpApplied = false;
	HypothesisScore score;
};

class PoseEstimator
{
public:
	explicit PoseEstimator(const EstimatorLimits &limits = {});

	const EstimatorLimits &limits() const { return limits_; }

	// Hypotheses are reported to the observer (nullptr: none). Not owned.
	void setObserver(EstimateObserver *observer) { observer_ = observer; }

	// Scores a given pose (model -> real camera) in the box as estimate()
	// scores its hypotheses. For diagnostics and tests.
	Expected<HypothesisScore> scorePose(ImageView<const float> depth, const CameraIntrinsics &K,
					    const PixelBox &box, const ObjectModel &model,
					    const EstimatorConfig &config, const Pose &pose);

	// depth: the whole frame in mm (0 = missing). box: x, y, w, h pixels.
	PoseEstimate estimate(ImageView<const float> depth, const CameraIntrinsics &K,
			      const PixelBox &box, const ObjectModel &model,
			      const EstimatorConfig &config);

private:
	struct Hypothesis {
		Pose pose; // virtual camera frame
		HypothesisScore score;
		int iteration = -1;
		bool valid = false;
	};

	int buildCloud(ImageView<const float> depth, const CameraIntrinsics &K,
		       const ModelParams &params);
	int voteOnce(const CameraIntrinsics &K, const ObjectModel &model,
		     const EstimatorConfig &config, int cloudCount, const UnitCubeFrame *frame,
		     int &parts);
	bool hypothesisFrame(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model,
			     UnitCubeFrame &frame);
	Hypothesis scoreModes(int iteration, size_t modeCount, const CameraIntrinsics &K,
			      const ObjectModel &model, const EstimatorConfig &config);
	void keep(const Hypothesis &h, float sameTranslationMm);
	void report(int iteration, const char *stage, int rank, const Pose &virtualPose,
		    const HypothesisScore &s, float density) const;
	HypothesisScore score(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model,
			      const EstimatorConfig &config);
	void maskToHypothesis(const HypothesisScore &s, const EstimatorConfig &config);
	void maskToRange(float lo, float hi);

	EstimatorLimits limits_;
	IbsFitter fitter_;
	PartExtractor extractor_;
	DepthRenderer renderer_;

	std::vector<float> observed_; // virtual crop
	std::vector<float> working_;  // masked crop (Eq. 10)
	std::vector<float> render_;
	ImageView<float> observedView_, workingView_, renderView_;

	std::vector<CloudPoint> cloud_;
	std::vector<Eigen::Vector3f> unit_, normals_;
	std::vector<ControlPoint> active_;
	std::vector<Part> parts_;
	std::vector<PartCp> pool_;
	std::vector<float> hist_;
	std::vector<CastVote> votes_;
	std::vector<float> modeScratch_;
	std::vector<Eigen::Vector3f> seeds_;
	std::vector<PoseMode> modes_;
	std::vector<int> windowHist_;
	std::vector<DepthWindow> windows_;
	std::vector<Hypothesis> kept_; // best distinct hypotheses, by score
	size_t keptCount_ = 0;
	Eigen::Matrix3d cropRotation_ = Eigen::Matrix3d::Identity();
	EstimateObserver *observer_ = nullptr;
};

} // namespace ihf
