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

namespace {

IbsLimits ibsLimits(const EstimatorLimits &limits)
{
	IbsLimits ibs;
	ibs.maxN = limits.maxIbsN;
	ibs.maxPoints = limits.maxIbsPoints;
	ibs.maxActive = limits.maxActive;
	return ibs;
}

PartLimits partLimits(const EstimatorLimits &limits)
{
	PartLimits pl;
	pl.maxPoints = limits.maxWindowPixels;
	pl.maxControlPoints = limits.maxActive;
	pl.maxBoxPixels = limits.maxWindowPixels;
	return pl;
}

size_t count(int n)
{
	return static_cast<size_t>(std::max(n, 0));
}

} // namespace

template<typename A>
bool PoseEstimator::carvePersistent(A &arena)
{
	const EstimatorLimits &l = limits_;
	return arenaTake(arena, observed_, count(l.maxWindowPixels)) &&
	       arenaTake(arena, active_, count(l.maxActive)) && arenaTake(arena, parts_, count(l.maxParts)) &&
	       arenaTake(arena, pool_, count(l.maxParts) * count(l.maxPartControlPoints)) &&
	       arenaTake(arena, hist_, count(l.maxHistogramDims)) &&
	       arenaTake(arena, votes_, count(l.maxVotes)) &&
	       arenaTake(arena, modeScratch_, count(l.maxVotes)) &&
	       arenaTake(arena, seeds_, count(l.maxModeSeeds)) && arenaTake(arena, modes_, count(l.maxModes));
}

template<typename A>
bool PoseEstimator::carveBox(A &arena, size_t pixels)
{
	return arenaTake(arena, working_, pixels) && arenaTake(arena, render_, pixels) &&
	       arenaTake(arena, cloud_, pixels) && arenaTake(arena, unit_, pixels) &&
	       arenaTake(arena, normals_, pixels);
}

size_t PoseEstimator::arenaBytes(const EstimatorLimits &limits)
{
	// The carve functions only record sizes on an ArenaSizer; a scratch
	// estimator over an empty arena provides the members to carve into.
	ArenaSizer sizer;
	PoseEstimator scratch(limits, nullptr, 0);
	scratch.carvePersistent(sizer);
	scratch.carveBox(sizer, count(limits.maxWindowPixels));
	return sizer.bytes + IbsFitter::arenaBytes(ibsLimits(limits)) +
	       PartExtractor::arenaBytes(partLimits(limits)) + DepthRenderer::arenaBytes(limits.maxMeshVertices);
}

PoseEstimator::PoseEstimator(const EstimatorLimits &limits, const Clock *clock, int)
	: limits_(limits), timer_(clock ? *clock : steadyClock_)
{
}

PoseEstimator::PoseEstimator(const EstimatorLimits &limits, const Clock *clock)
	: limits_(limits), timer_(clock ? *clock : steadyClock_)
{
	auto arena = Arena::create(arenaBytes(limits));
	if (!arena)
		return;
	arena_ = std::move(*arena);
	valid_ = fitter_.reserve(ibsLimits(limits), arena_).ok() &&
		 extractor_.reserve(partLimits(limits), arena_).ok() &&
		 renderer_.reserve(limits.maxMeshVertices, arena_).ok() && carvePersistent(arena_);
	persistentBytes_ = arena_.used();
}

void PoseEstimator::beginFrame(int boxes, float budgetMs)
{
	budget_.beginFrame(timer_.clock().nowNs(), static_cast<int64_t>(budgetMs * 1e6), boxes);
}

void PoseEstimator::endFrame()
{
	// The frame ends with its last box's last stage.
	budget_.endFrame(timer_.last());
}

PoseEstimator::BoxScope::BoxScope(PoseEstimator &e, const EstimatorConfig &config)
	: e_(e), scratch_(e.arena_), ownFrame_(!e.budget_.inFrame())
{
	if (ownFrame_)
		e_.beginFrame(1, config.frameBudgetMs);
	e_.budget_.beginBox(e_.timer_.start());
}

PoseEstimator::BoxScope::~BoxScope()
{
	// The box ends with its last stage (what follows it is bookkeeping).
	const int64_t now = e_.timer_.last();
	e_.budget_.endBox(now);
	if (ownFrame_)
		e_.budget_.endFrame(now);
	e_.working_ = e_.render_ = {};
	e_.cloud_ = {};
	e_.unit_ = e_.normals_ = {};
}

bool PoseEstimator::refinementFits(const EstimatorConfig &config)
{
	int64_t predicted = costs_.predict({Stage::kCloud, Stage::kNormalise, Stage::kIbsFit, Stage::kParts,
					    Stage::kHocp, Stage::kForest, Stage::kModes, Stage::kScore});
	// Keep room for the polish after the last iteration.
	if (config.icp)
		predicted += costs_.average(Stage::kIcp);
	if (budget_.fits(timer_.now(), predicted))
		return true;
	++budgetStops_;
	return false;
}

bool PoseEstimator::icpFits()
{
	if (budget_.fits(timer_.now(), costs_.average(Stage::kIcp)))
		return true;
	++icpSkipped_;
	return false;
}

EstimatorStats PoseEstimator::stats() const
{
	EstimatorStats s;
	s.stages = timer_.counters();
	s.frames = budget_.frames();
	s.boxes = budget_.boxes();
	s.iterations = iterationsRun_;
	s.budgetStops = budgetStops_;
	s.icpSkipped = icpSkipped_;
	s.frameOverruns = budget_.frameOverruns();
	s.boxOverruns = budget_.boxOverruns();
	s.worstFrameNs = budget_.worstFrameNs();
	s.arenaCapacity = arena_.capacity();
	s.arenaPersistent = persistentBytes_;
	s.arenaHighWater = arena_.highWater();
	s.peaks = peaks_;
	return s;
}

int PoseEstimator::buildCloud(ImageView<const float> depth, const CameraIntrinsics &K,
			      const ModelParams &params)
{
	auto n = cloudFromDepth(depth, K, PixelBox{0, 0, depth.width, depth.height}, params.cloud,
				cloud_);
	timer_.lap(Stage::kCloud);
	const int points = n ? *n : 0;
	peaks_.cloudPoints = std::max(peaks_.cloudPoints, points);
	return points;
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
	timer_.lap(Stage::kNormalise);
	auto fit = fitter_.fit(std::span(unit_.data(), cloud.size()),
			       std::span(normals_.data(), cloud.size()), params.ibs, active_);
	timer_.lap(Stage::kIbsFit);
	if (!fit)
		return 0;
	peaks_.activeControlPoints = std::max(peaks_.activeControlPoints, fit->activeCount);
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
	timer_.lap(Stage::kParts);
	if (!parts)
		return 0;
	partCount = *parts;
	peaks_.parts = std::max(peaks_.parts, partCount);
	if (partCount > 0) {
		const Part &last = parts_[partCount - 1];
		peaks_.poolControlPoints = std::max(peaks_.poolControlPoints,
						    static_cast<int>(last.cpOffset + last.cpCount));
	}

	// Two passes so that the stage counters can tell the HoCP keys from the
	// forest walk (whose depth-checked histograms depend on each node).
	const float mmPerUnit = frame->mmPerUnit();
	for (int i = 0; i < partCount; ++i) {
		Part &p = parts_[i];
		partToMillimetres(std::span(pool_.data() + p.cpOffset, p.cpCount), p.zMin, p.zMax,
				  mmPerUnit, params.hocp);
	}
	timer_.lap(Stage::kHocp);
	std::span<float> hist(hist_.data(), model.forest().dims);
	size_t votes = 0;
	for (int i = 0; i < partCount; ++i) {
		const Part &p = parts_[i];
		std::span<const PartCp> cps(pool_.data() + p.cpOffset, p.cpCount);
		votes = castPartVotes(model.forest(), cps, p.centreCamera, params.hocp,
				      params.depthCheckMarginMm, hist, votes_, votes);
	}
	timer_.lap(Stage::kForest);
	peaks_.votes = std::max(peaks_.votes, static_cast<int>(votes));
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
	BoxScope scope(*this, config);
	if (!valid_) {
		out.reason = "estimator has no memory (arena allocation failed)";
		return out;
	}
	if (model.mesh().vertices.size() > renderer_.capacity()) {
		out.reason = "model mesh larger than the estimator's render limit";
		return out;
	}
	if (model.forest().dims > limits_.maxHistogramDims) {
		out.reason = "forest histogram longer than the estimator's limit";
		return out;
	}
	VirtualCrop cropStorage;
	const CropStatus cropStatus = makeVirtualCrop(depth, K, box, observed_, cropStorage);
	timer_.lap(Stage::kCrop);
	if (cropStatus != CropStatus::kOk) {
		out.reason = cropStatus == CropStatus::kOutsideImage ? "box outside the image" : "empty box";
		return out;
	}
	const VirtualCrop *crop = &cropStorage;
	if (crop->validPixels < config.minValidPixels) {
		out.reason = "too few valid depth pixels in the box";
		return out;
	}
	const CameraIntrinsics &vk = crop->intrinsics;
	const int w = vk.width, h = vk.height;
	peaks_.windowPixels = std::max(peaks_.windowPixels, w * h);
	if (!carveBox(arena_, static_cast<size_t>(w) * h)) {
		out.reason = "arena too small for the box";
		return out;
	}
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
		if (k > 0 && !refinementFits(config)) {
			out.budgetStopped = true;
			break;
		}
		const StageTotals iterationStart = timer_.totals();
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
		timer_.lap(Stage::kModes);
		Hypothesis h = bestMode(modes, vk, model, config);
		timer_.lap(Stage::kScore);
		costs_.observe(iterationStart, timer_.totals());
		iterationsRun_ += k > 0;
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

	const bool polish = config.icp && icpFits();
	out.icpSkipped = config.icp && !polish;
	if (polish) {
		const int64_t icpStart = timer_.last();
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
		// The cost model sees the whole polish (its cloud is counted
		// under the cloud stage).
		costs_.observe(Stage::kIcp, timer_.lap(Stage::kIcp) - icpStart);
	}

	out.found = true;
	out.pose.R = crop->rotation * best.pose.R;
	out.pose.t = crop->rotation * best.pose.t;
	out.score = best.score;
	out.confidence = best.score.score;
	return out;
}

} // namespace ihf
