// SPDX-License-Identifier: MIT
#include "core/estimation/pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
	modes_.resize(static_cast<size_t>(std::max(1, limits.maxModes)));
	kept_.resize(static_cast<size_t>(std::max(1, limits.maxCandidates)));
	windowHist_.resize(1024);
	windows_.resize(8);
}

void PoseEstimator::report(int iteration, const char *stage, int rank, const Pose &virtualPose,
			   const HypothesisScore &s, float density) const
{
	if (!observer_)
		return;
	HypothesisEvent e;
	e.iteration = iteration;
	e.stage = stage;
	e.rank = rank;
	e.pose.R = cropRotation_ * virtualPose.R;
	e.pose.t = cropRotation_ * virtualPose.t;
	e.score = s;
	e.voteDensity = density;
	observer_->onHypothesis(e);
}

// Keeps the best distinct hypotheses sorted by score; a near duplicate of a
// kept one replaces it only if it scores higher.
void PoseEstimator::keep(const Hypothesis &h, float sameTranslationMm)
{
	constexpr double kSameRotation = 10.0 * M_PI / 180.0;
	for (size_t i = 0; i < keptCount_; ++i) {
		Hypothesis &k = kept_[i];
		if ((k.pose.t - h.pose.t).norm() < sameTranslationMm &&
		    rotationAngle(k.pose.R, h.pose.R) < kSameRotation) {
			if (h.score.score <= k.score.score)
				return;
			// Remove it; the new one is inserted below.
			std::move(kept_.begin() + i + 1, kept_.begin() + keptCount_, kept_.begin() + i);
			--keptCount_;
			break;
		}
	}
	size_t pos = 0;
	while (pos < keptCount_ && kept_[pos].score.score >= h.score.score)
		++pos;
	if (pos >= kept_.size())
		return;
	if (keptCount_ < kept_.size())
		++keptCount_;
	std::move_backward(kept_.begin() + pos, kept_.begin() + keptCount_ - 1, kept_.begin() + keptCount_);
	kept_[pos] = h;
}

int PoseEstimator::buildCloud(ImageView<const float> depth, const CameraIntrinsics &K,
			      const ModelParams &params)
{
	auto n = cloudFromDepth(depth, K, PixelBox{0, 0, depth.width, depth.height}, params.cloud,
				cloud_);
	return n ? *n : 0;
}

bool PoseEstimator::hypothesisFrame(const Pose &pose, const CameraIntrinsics &K,
				    const ObjectModel &model, UnitCubeFrame &frame)
{
	renderView_.fill(0.0f);
	if (!renderer_.render(model.mesh(), pose, K, renderView_))
		return false;
	Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
	Eigen::Vector3f hi = -lo;
	for (int y = 0; y < renderView_.height; ++y)
		for (int x = 0; x < renderView_.width; ++x) {
			float z = renderView_.at(x, y);
			if (!(z > 0))
				continue;
			Eigen::Vector3f p = K.backProject(x, y, z).cast<float>();
			lo = lo.cwiseMin(p);
			hi = hi.cwiseMax(p);
		}
	if (!(hi.x() >= lo.x()))
		return false;
	frame.centre = 0.5f * (lo + hi);
	frame.alpha = std::max((hi - lo).maxCoeff(), 1.0f);
	frame.scale = 1.0f;
	return true;
}

int PoseEstimator::voteOnce(const CameraIntrinsics &K, const ObjectModel &model,
			    const EstimatorConfig &config, int cloudCount,
			    const UnitCubeFrame *frameOverride, int &partCount)
{
	const ModelParams &params = model.params();
	partCount = 0;
	Expected<UnitCubeFrame> frame = frameOverride
		? Expected<UnitCubeFrame>(*frameOverride)
		: makeUnitCubeFrame(std::span<const CloudPoint>(cloud_.data(), cloudCount), 1.0f);
	if (!frame)
		return 0;
	toUnitCube(std::span<const CloudPoint>(cloud_.data(), cloudCount), *frame,
		   std::span(unit_.data(), cloudCount), std::span(normals_.data(), cloudCount));
	if (frameOverride) {
		// Only the points inside the hypothesis' cube take part.
		int kept = 0;
		for (int i = 0; i < cloudCount; ++i) {
			const Eigen::Vector3f &u = unit_[i];
			if ((u.array() < 0.0f).any() || (u.array() > 1.0f).any())
				continue;
			cloud_[kept] = cloud_[i];
			unit_[kept] = unit_[i];
			normals_[kept] = normals_[i];
			++kept;
		}
		cloudCount = kept;
		if (cloudCount < config.minValidPixels)
			return 0;
	}
	std::span<const CloudPoint> cloud(cloud_.data(), cloudCount);
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
	HypothesisScore s = scoreHypothesis(observedView_, renderView_, config.score);
	s.boxFactor = boxAgreement(model.mesh(), pose, K, config.score);
	s.score = s.depthScore * s.boxFactor;
	return s;
}

// Scores every vote mode (translation modes x their rotation modes), keeps
// the distinct good ones, and returns this iteration's best.
PoseEstimator::Hypothesis PoseEstimator::scoreModes(int iteration, size_t modeCount,
						    const CameraIntrinsics &K, const ObjectModel &model,
						    const EstimatorConfig &config)
{
	Hypothesis best;
	const float same = static_cast<float>(0.05 * model.params().diameter);
	for (size_t m = 0; m < modeCount; ++m) {
		Hypothesis h;
		h.pose.R = modes_[m].rotation.toRotationMatrix().cast<double>();
		h.pose.t = modes_[m].centre.cast<double>();
		if (h.pose.t.z() <= 0)
			continue;
		h.score = score(h.pose, K, model, config);
		h.iteration = iteration;
		h.valid = true;
		report(iteration, "mode", static_cast<int>(m), h.pose, h.score, modes_[m].rotationDensity);
		keep(h, same);
		if (!best.valid || h.score.score > best.score.score)
			best = h;
	}
	return best;
}

Expected<HypothesisScore> PoseEstimator::scorePose(ImageView<const float> depth,
						   const CameraIntrinsics &K, const PixelBox &box,
						   const ObjectModel &model,
						   const EstimatorConfig &config, const Pose &pose)
{
	if (model.mesh().vertices.size() > renderer_.capacity())
		return makeError(Errc::kCapacity, "model mesh larger than the estimator's render limit");
	auto crop = makeVirtualCrop(depth, K, box,
				    std::span(observed_.data(), static_cast<size_t>(limits_.maxWindowPixels)));
	if (!crop)
		return crop.error();
	const CameraIntrinsics &vk = crop->intrinsics;
	observedView_ = ImageView<float>(observed_.data(), vk.width, vk.height, vk.width);
	renderView_ = ImageView<float>(render_.data(), vk.width, vk.height, vk.width);
	Pose virt;
	virt.R = crop->rotation.transpose() * pose.R;
	virt.t = crop->rotation.transpose() * pose.t;
	return score(virt, vk, model, config);
}

void PoseEstimator::maskToHypothesis(const HypothesisScore &s, const EstimatorConfig &config)
{
	maskToRange(s.depthMin * config.psi1, s.depthMax * config.psi2);
}

void PoseEstimator::maskToRange(float lo, float hi)
{
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

	cropRotation_ = crop->rotation;
	keptCount_ = 0;
	modeCfg.rotationModesPerCentre = std::max(1, config.rotationModes);
	const size_t modeSlots = std::min(modes_.size(),
					  static_cast<size_t>(std::max(1, config.maxHypotheses)) *
						  static_cast<size_t>(modeCfg.rotationModesPerCentre));
	size_t windows = 0;
	if (config.depthWindows > 0)
		windows = findDepthWindows(observedView_,
					   static_cast<float>(config.depthWindowWidth * params.diameter),
					   windowHist_,
					   std::span(windows_.data(), std::min(windows_.size(),
									       static_cast<size_t>(config.depthWindows))));
	UnitCubeFrame cube;
	bool haveFrame = false;
	for (int k = 0; k <= config.iterations; ++k) {
		// The initial registration votes once per depth window (or once on
		// the whole box); refinement once on the masked crop.
		const size_t passes = k == 0 ? std::max<size_t>(1, windows) : 1;
		Hypothesis iterBest;
		for (size_t pass = 0; pass < passes; ++pass) {
			if (k == 0 && windows > 0)
				maskToRange(windows_[pass].nearMm, windows_[pass].farMm);
			int n = buildCloud(workingView_, vk, params);
			if (n < config.minValidPixels)
				continue;
			int partCount = 0;
			int votes = voteOnce(vk, model, config, n, k > 0 && haveFrame ? &cube : nullptr,
					     partCount);
			out.parts = partCount;
			out.votes = votes;
			if (votes == 0)
				continue;
			size_t modes = findPoseModes(std::span(votes_.data(), votes), modeCfg,
						     {modeScratch_, seeds_}, std::span(modes_.data(), modeSlots));
			Hypothesis h = scoreModes(k, modes, vk, model, config);
			if (h.valid && (!iterBest.valid || h.score.score > iterBest.score.score))
				iterBest = h;
		}
		if (!iterBest.valid)
			break;
		out.iterationsDone = k;
		// Eq. 10: the next iteration sees only this iteration's best
		// hypothesis' depth range.
		if (k < config.iterations) {
			maskToHypothesis(iterBest.score, config);
			haveFrame = config.hypothesisCube && hypothesisFrame(iterBest.pose, vk, model, cube);
		}
	}
	if (keptCount_ == 0) {
		out.reason = "no vote mode (no parts could be described)";
		return out;
	}
	Hypothesis best = kept_[0];

	if (config.icp) {
		// Polish the best distinct hypotheses; each sees the crop cut to its
		// own depth range, and the best score after ICP wins.
		const size_t polish = std::min(keptCount_, static_cast<size_t>(std::max(0, config.icpCandidates)));
		for (size_t c = 0; c < polish; ++c) {
			const Hypothesis &cand = kept_[c];
			maskToHypothesis(cand.score, config);
			int n = buildCloud(workingView_, vk, params);
			IcpResult icp = refineIcp(std::span(cloud_.data(), n), model.mesh(), cand.pose, vk,
						  renderer_, renderView_, config.icpConfig);
			if (icp.iterations == 0)
				continue;
			HypothesisScore s = score(icp.pose, vk, model, config);
			report(cand.iteration, "icp", static_cast<int>(c), icp.pose, s, 0);
			if (s.score > best.score.score) {
				best.pose = icp.pose;
				best.score = s;
				best.iteration = cand.iteration;
				out.icpApplied = true;
			}
		}
	}
	out.bestIteration = best.iteration;

	out.found = true;
	out.pose.R = crop->rotation * best.pose.R;
	out.pose.t = crop->rotation * best.pose.t;
	out.score = best.score;
	out.confidence = best.score.score;
	return out;
}

} // namespace ihf
