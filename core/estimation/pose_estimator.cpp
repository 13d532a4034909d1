// SPDX-License-Identifier: MIT
#include "core/estimation/pose_estimator.h"

#include <algorithm>
#include <cmath>

#include "core/estimation/forest_walker.h"
#include "core/estimation/virtual_crop.h"
#include "core/features/depth_cloud.h"
#include "core/features/part_units.h"
#include "core/features/unit_cube_frame.h"

namespace ihf {

PoseEstimator::PoseEstimator(const EstimatorLimits &limits)
	: limits_(limits), renderer_(limits.maxMeshVertices)
{
	IbsLimits ibs;
	ibs.maxN = limits.maxIbsN;
	ibs.maxPoints = limits.maxIbsPoints;
	ibs.maxActive = limits.maxActive;
	fitter_.reserve(ibs);
	PartLimits pl;
	pl.maxPoints = limits.maxWindowPixels;
	pl.maxControlPoints = limits.maxActive;
	pl.maxBoxPixels = limits.maxWindowPixels;
	extractor_.reserve(pl);

	const size_t px = static_cast<size_t>(limits.maxWindowPixels);
	observed_.resize(px);
	working_.resize(px);
	render_.resize(px);
	cloud_.resize(px);
	unit_.resize(px);
	normals_.resize(px);
	active_.resize(limits.maxActive);
	parts_.resize(limits.maxParts);
	pool_.resize(static_cast<size_t>(limits.maxParts) * limits.maxPartControlPoints);
	hist_.resize(1024);
	votes_.resize(limits.maxVotes);
	modeScratch_.resize(limits.maxVotes);
	seeds_.resize(64);
	modes_.resize(8);
}

int PoseEstimator::buildCloud(ImageView<const float> depth, const CameraIntrinsics &K,
			      const ModelParams &params)
{
	auto n = cloudFromDepth(depth, K, PixelBox{0, 0, depth.width, depth.height}, params.cloud,
				cloud_);
	return n ? *n : 0;
}

int PoseEstimator::voteOnce(const CameraIntrinsics &K, const ObjectModel &model,
			    const EstimatorConfig &config, int cloudCount, int &partCount)
{
	const ModelParams &params = model.params();
	std::span<const CloudPoint> cloud(cloud_.data(), cloudCount);
	partCount = 0;
	auto frame = makeUnitCubeFrame(cloud, 1.0f);
	if (!frame)
		return 0;
	toUnitCube(cloud, *frame, std::span(unit_.data(), cloud.size()),
		   std::span(normals_.data(), cloud.size()));
	auto fit = fitter_.fit(std::span(unit_.data(), cloud.size()),
			       std::span(normals_.data(), cloud.size()), params.ibs, active_);
	if (!fit)
		return 0;
	PartSource src;
	src.cloud = cloud;
	src.unit = std::span(unit_.data(), cloud.size());
	src.cps = std::span(active_.data(), fit->activeCount);
	src.frame = *frame;
	src.intrinsics = K;
	src.latticeDelta = fitter_.lattice().delta();
	if (!extractor_.prepare(src))
		return 0;
	PartConfig partCfg = params.parts;
	if (config.partStride > 0)
		partCfg.stride = config.partStride;
	partCfg.maxControlPoints = std::min(partCfg.maxControlPoints, limits_.maxPartControlPoints);
	auto parts = extractor_.extractAll(partCfg, params.hocp, parts_, pool_);
	if (!parts)
		return 0;
	partCount = *parts;

	const float mmPerUnit = frame->mmPerUnit();
	std::span<float> hist(hist_.data(), model.forest().dims);
	size_t votes = 0;
	for (int i = 0; i < partCount; ++i) {
		Part &p = parts_[i];
		std::span<PartCp> cps(pool_.data() + p.cpOffset, p.cpCount);
		partToMillimetres(cps, p.zMin, p.zMax, mmPerUnit, params.hocp);
		votes = castPartVotes(model.forest(), cps, p.centreCamera, params.hocp,
				      params.depthCheckMarginMm, hist, votes_, votes);
	}
	return static_cast<int>(votes);
}

HypothesisScore PoseEstimator::score(const Pose &pose, const CameraIntrinsics &K,
				     const ObjectModel &model, const EstimatorConfig &config)
{
	renderView_.fill(0.0f);
	if (!renderer_.render(model.mesh(), pose, K, renderView_))
		return {};
	return scoreHypothesis(observedView_, renderView_, config.score);
}

PoseEstimator::Hypothesis PoseEstimator::bestMode(size_t modeCount, const CameraIntrinsics &K,
						  const ObjectModel &model,
						  const EstimatorConfig &config)
{
	Hypothesis best;
	for (size_t m = 0; m < modeCount && m < static_cast<size_t>(config.maxHypotheses); ++m) {
		Pose pose;
		pose.R = modes_[m].rotation.toRotationMatrix().cast<double>();
		pose.t = modes_[m].centre.cast<double>();
		if (pose.t.z() <= 0)
			continue;
		HypothesisScore s = score(pose, K, model, config);
		if (!best.valid || s.score > best.score.score) {
			best.pose = pose;
			best.score = s;
			best.valid = true;
		}
	}
	return best;
}

void PoseEstimator::maskToHypothesis(const HypothesisScore &s, const EstimatorConfig &config)
{
	const float lo = s.depthMin * config.psi1, hi = s.depthMax * config.psi2;
	const size_t n = static_cast<size_t>(observedView_.width) * observedView_.height;
	for (size_t i = 0; i < n; ++i) {
		float d = observed_[i];
		working_[i] = (d > lo && d < hi) ? d : 0.0f;
	}
}

PoseEstimate PoseEstimator::estimate(ImageView<const float> depth, const CameraIntrinsics &K,
				     const PixelBox &box, const ObjectModel &model,
				     const EstimatorConfig &config)
{
	PoseEstimate out;
	if (model.mesh().vertices.size() > renderer_.capacity()) {
		out.reason = "model mesh larger than the estimator's render limit";
		return out;
	}
	auto crop = makeVirtualCrop(depth, K, box,
				    std::span(observed_.data(), static_cast<size_t>(limits_.maxWindowPixels)));
	if (!crop) {
		out.reason = crop.error().code == Errc::kOutOfRange ? "box outside the image" : "empty box";
		return out;
	}
	if (crop->validPixels < config.minValidPixels) {
		out.reason = "too few valid depth pixels in the box";
		return out;
	}
	const CameraIntrinsics &vk = crop->intrinsics;
	const int w = vk.width, h = vk.height;
	observedView_ = ImageView<float>(observed_.data(), w, h, w);
	workingView_ = ImageView<float>(working_.data(), w, h, w);
	renderView_ = ImageView<float>(render_.data(), w, h, w);
	std::copy_n(observed_.data(), static_cast<size_t>(w) * h, working_.data());

	const ModelParams &params = model.params();
	VoteModeConfig modeCfg;
	modeCfg.translationBandwidth = static_cast<float>(config.translationBandwidth * params.diameter);
	modeCfg.rotationBandwidth = config.rotationBandwidthDeg * static_cast<float>(M_PI / 180.0);

	Hypothesis best;
	for (int k = 0; k <= config.iterations; ++k) {
		int n = buildCloud(workingView_, vk, params);
		if (n < config.minValidPixels)
			break;
		int partCount = 0;
		int votes = voteOnce(vk, model, config, n, partCount);
		out.parts = partCount;
		out.votes = votes;
		out.iterationsDone = k;
		if (votes == 0)
			break;
		size_t modes = findPoseModes(std::span(votes_.data(), votes), modeCfg,
					     {modeScratch_, seeds_}, modes_);
		Hypothesis h = bestMode(modes, vk, model, config);
		if (!h.valid)
			break;
		if (!best.valid || h.score.score > best.score.score) {
			best = h;
			out.bestIteration = k;
		}
		if (k < config.iterations)
			maskToHypothesis(h.score, config);
	}
	if (!best.valid) {
		out.reason = "no vote mode (no parts could be described)";
		return out;
	}

	if (config.icp) {
		maskToHypothesis(best.score, config);
		int n = buildCloud(workingView_, vk, params);
		IcpResult icp = refineIcp(std::span(cloud_.data(), n), model.mesh(), best.pose, vk,
					  renderer_, renderView_, config.icpConfig);
		HypothesisScore s = score(icp.pose, vk, model, config);
		if (icp.iterations > 0 && s.score >= best.score.score) {
			best.pose = icp.pose;
			best.score = s;
			out.icpApplied = true;
		}
	}

	out.found = true;
	out.pose.R = crop->rotation * best.pose.R;
	out.pose.t = crop->rotation * best.pose.t;
	out.score = best.score;
	out.confidence = best.score.score;
	return out;
}

} // namespace ihf
