// SPDX-License-Identifier: MIT
#include "core/tracking/track_refiner.h"

#include <algorithm>
#include <cmath>

#include "core/estimation/icp_polisher.h"
#include "core/estimation/pose_scorer.h"
#include "core/estimation/rival_poses.h"
#include "core/estimation/virtual_crop.h"
#include "core/pose/half_turns.h"

namespace ihf {

const char *trackVerdictName(TrackVerdict verdict)
{
	switch (verdict) {
	case TrackVerdict::kKept:
		return "kept";
	case TrackVerdict::kNoDepth:
		return "too few depth pixels in the box";
	case TrackVerdict::kOutsideBox:
		return "the predicted pose lies outside the box";
	case TrackVerdict::kNoFit:
		return "ICP found too few correspondences";
	case TrackVerdict::kLowScore:
		return "the score fell";
	case TrackVerdict::kLeftBox:
		return "the pose left its box";
	case TrackVerdict::kJumped:
		return "the polish jumped from the prediction";
	case TrackVerdict::kRival:
		return "a turned pose scores as well";
	case TrackVerdict::kNoMemory:
		return "the box or mesh exceeds the tracker's buffers";
	}
	return "?";
}

template<typename A>
bool TrackRefiner::carve(A &arena, size_t pixels)
{
	return arenaTake(arena, observed_, pixels) && arenaTake(arena, mask_, pixels) &&
	       arenaTake(arena, render_, pixels) && arenaTake(arena, cloud_, pixels);
}

size_t TrackRefiner::arenaBytes(int windowPixels, size_t maxMeshVertices)
{
	ArenaSizer sizer;
	TrackRefiner scratch;
	scratch.carve(sizer, static_cast<size_t>(std::max(1, windowPixels)));
	return sizer.bytes + DepthRenderer::arenaBytes(maxMeshVertices);
}

Status TrackRefiner::reserve(int windowPixels, size_t maxMeshVertices, Arena &arena)
{
	if (!carve(arena, static_cast<size_t>(std::max(1, windowPixels))))
		return makeError(Errc::kCapacity, "tracker arena too small for its window");
	return renderer_.reserve(maxMeshVertices, arena);
}

TrackRefinement TrackRefiner::refine(ImageView<const float> depth, const CameraIntrinsics &K, const PixelBox &box,
				     const ObjectModel &model, const EstimatorConfig &config,
				     const TrackerConfig &tracking, const Pose &predicted, float detectionScore,
				     float detectionMargin)
{
	TrackRefinement out;
	out.estimate.reason = "tracked pose not kept";
	if (model.renderMesh().vertices.size() > renderer_.capacity()) {
		out.verdict = TrackVerdict::kNoMemory;
		return out;
	}
	renderer_.setCullBackFaces(config.cullBackFaces && model.renderMeshClosed());
	VirtualCrop crop;
	std::span<float> window = observed_;
	if (tracking.windowPixels > 0 && static_cast<size_t>(tracking.windowPixels) < window.size())
		window = window.first(static_cast<size_t>(tracking.windowPixels));
	if (makeVirtualCrop(depth, K, box, window, crop) != CropStatus::kOk ||
	    crop.validPixels < config.minValidPixels) {
		out.verdict = TrackVerdict::kNoDepth;
		return out;
	}
	const CameraIntrinsics &vk = crop.intrinsics;
	const ImageView<float> observed(observed_.data(), vk.width, vk.height, vk.width);
	const ImageView<float> render(render_.data(), vk.width, vk.height, vk.width);
	const OpenSides open = openSidesOf(box.x, box.y, box.w, box.h, depth.width, depth.height);
	const ScoreWindow scoreWindow{observed, vk, open, &config.score, crop.downsample};
	const Eigen::Matrix3d Rv = crop.rotation;
	const Pose start{Rv.transpose() * predicted.R, Rv.transpose() * predicted.t};

	const HypothesisScore predictedScore = scoreInWindow(scoreWindow, renderer_, render, model, start);
	if (predictedScore.rendered == 0) {
		out.verdict = TrackVerdict::kOutsideBox;
		return out;
	}
	const PolishBuffers buffers{mask_.first(observed_.size()), cloud_, &renderer_, render};
	const PolishResult polished =
		polishInWindow(scoreWindow, model, start, predictedScore.depthMin * config.psi1,
			       predictedScore.depthMax * config.psi2, tracking.icp, buffers);
	const ModelParams &params = model.params();
	// The polish is taken when it stayed near the prediction and scores at
	// least as well; else the prediction itself stands, if it still holds
	// (an object at rest whose ICP slides off a poor fit keeps its pose, and
	// costs no detection).
	const bool jumped = polished.valid && !withinStep(tracking, polished.pose, start, params.diameter);
	const bool takePolish = polished.valid && !jumped && polished.score.score >= predictedScore.score;
	const Pose chosen = takePolish ? polished.pose : start;
	const HypothesisScore &s = takePolish ? polished.score : predictedScore;
	PoseEstimate &e = out.estimate;
	e.score = s;
	e.pose.R = Rv * chosen.R;
	e.pose.t = Rv * chosen.t;
	e.margin = config.confidence.fullMargin;
	e.confidence = poseConfidence(s.score, e.margin, config.confidence);
	e.icpApplied = takePolish;
	e.bestIteration = 0;
	out.scored = true;
	if (s.score < tracking.minScore || s.score < tracking.keepShare * detectionScore) {
		out.verdict = jumped ? TrackVerdict::kJumped : polished.valid ? TrackVerdict::kLowScore : TrackVerdict::kNoFit;
		return out;
	}
	if (s.boxFactor < tracking.minBoxFactor) {
		out.verdict = TrackVerdict::kLeftBox;
		return out;
	}
	// The rivals: the pose turned half round about the model's box axes
	// (the turns a detection most often confuses), as the confidence's
	// margin measures them for a detection.
	float margin = e.margin;
	if (tracking.rivals && !params.symmetric) {
		const Eigen::Vector3d centre = boundingBox(model.mesh()).centre().cast<double>();
		float rival = 0;
		HalfTurnConfig boxAxesOnly;
		boxAxesOnly.axes = 0;
		for (int axis = 0; axis < halfTurnCount(boxAxesOnly); ++axis) {
			const Pose turned = turnedAbout(chosen, halfTurnOf(boxAxesOnly, axis), centre);
			rival = std::max(rival, scoreInWindow(scoreWindow, renderer_, render, model, turned).score);
		}
		margin = std::max(0.0f, s.score - rival);
		e.margin = margin;
		e.confidence = poseConfidence(s.score, margin, config.confidence);
		if (margin < tracking.rivalMargin && detectionMargin >= tracking.rivalMargin) {
			out.verdict = TrackVerdict::kRival;
			return out;
		}
	}
	out.verdict = TrackVerdict::kKept;
	e.found = true;
	e.reason = "";
	return out;
}

} // namespace ihf
