// SPDX-License-Identifier: MIT
#include "core/estimation/hough_voter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/estimation/forest_walker.h"
#include "core/features/depth_cloud.h"
#include "core/features/part_units.h"

namespace ihf {

int HoughVoter::buildCloud(ImageView<const float> depth, const CameraIntrinsics &K, const ModelParams &params)
{
	auto n = cloudFromDepth(depth, K, PixelBox{0, 0, depth.width, depth.height}, params.cloud, workspace_.cloud());
	timer_.lap(Stage::kCloud);
	const int points = n ? *n : 0;
	peaks_.cloudPoints = std::max(peaks_.cloudPoints, points);
	return points;
}

VoteCount HoughVoter::vote(const CameraIntrinsics &K, const ObjectModel &model, const EstimatorConfig &config,
			   int cloudPoints, const UnitCubeFrame *frameOverride)
{
	const ModelParams &params = model.params();
	const std::span<CloudPoint> cloudBuffer = workspace_.cloud();
	const std::span<Eigen::Vector3f> unit = workspace_.unit(), normals = workspace_.normals();
	VoteBuffers &buffers = workspace_.votes();
	size_t n = static_cast<size_t>(cloudPoints);
	Expected<UnitCubeFrame> frame = frameOverride ? Expected<UnitCubeFrame>(*frameOverride)
						      : makeUnitCubeFrame(cloudBuffer.first(n), 1.0f);
	if (!frame)
		return {};
	toUnitCube(cloudBuffer.first(n), *frame, unit.first(n), normals.first(n));
	if (frameOverride) {
		// Only the points inside the hypothesis' cube take part.
		size_t kept = 0;
		for (size_t i = 0; i < n; ++i) {
			const Eigen::Vector3f &u = unit[i];
			if ((u.array() < 0.0f).any() || (u.array() > 1.0f).any())
				continue;
			cloudBuffer[kept] = cloudBuffer[i];
			unit[kept] = unit[i];
			normals[kept] = normals[i];
			++kept;
		}
		n = kept;
		if (static_cast<int>(n) < config.minValidPixels)
			return {};
	}
	const std::span<const CloudPoint> cloud = cloudBuffer.first(n);
	timer_.lap(Stage::kNormalise);

	IbsConfig ibs = params.ibs;
	if (config.ibsMaxPoints > 0)
		ibs.maxPoints = std::min(ibs.maxPoints, config.ibsMaxPoints);
	if (config.ibsCgIterations > 0)
		ibs.cgMaxIterations = std::min(ibs.cgMaxIterations, config.ibsCgIterations);
	IbsFitter &fitter = workspace_.fitter();
	auto fit = fitter.fit(unit.first(n), normals.first(n), ibs, buffers.active, {}, &workspace_.workers());
	timer_.lap(Stage::kIbsFit);
	if (!fit)
		return {};
	peaks_.activeControlPoints = std::max(peaks_.activeControlPoints, fit->activeCount);

	PartSource src;
	src.cloud = cloud;
	src.unit = unit.first(n);
	src.cps = std::span(buffers.active.data(), fit->activeCount);
	src.frame = *frame;
	src.intrinsics = K;
	src.latticeDelta = fitter.lattice().delta();
	PartExtractor &extractor = workspace_.extractor();
	if (!extractor.prepare(src))
		return {};
	PartConfig partCfg = params.parts;
	if (config.partStride > 0)
		partCfg.stride = config.partStride;
	// Large (near or big) objects: a wider stride keeps the part count near
	// targetParts, so the vote buffer never truncates the last rows' votes
	// and the time per box stays bounded.
	if (config.targetParts > 0) {
		const int wide = static_cast<int>(
			std::ceil(std::sqrt(static_cast<float>(static_cast<int>(n)) / config.targetParts)));
		partCfg.stride = std::max(partCfg.stride, wide);
	}
	partCfg.maxControlPoints = std::min(partCfg.maxControlPoints, workspace_.limits().maxPartControlPoints);
	auto parts = extractor.extractAll(partCfg, params.hocp, buffers.parts, buffers.pool);
	timer_.lap(Stage::kParts);
	if (!parts)
		return {};
	VoteCount out;
	out.parts = *parts;
	peaks_.parts = std::max(peaks_.parts, out.parts);
	if (out.parts > 0) {
		const Part &last = buffers.parts[static_cast<size_t>(out.parts - 1)];
		peaks_.poolControlPoints =
			std::max(peaks_.poolControlPoints, static_cast<int>(last.cpOffset + last.cpCount));
	}

	// Two passes so that the stage counters can tell the HoCP keys from the
	// forest walk (whose depth-checked histograms depend on each node).
	const float mmPerUnit = frame->mmPerUnit();
	for (int i = 0; i < out.parts; ++i) {
		Part &p = buffers.parts[static_cast<size_t>(i)];
		partToMillimetres(std::span(buffers.pool.data() + p.cpOffset, p.cpCount), p.zMin, p.zMax, mmPerUnit,
				  params.hocp);
	}
	timer_.lap(Stage::kHocp);
	const size_t votes = castVotes(model, out.parts);
	timer_.lap(Stage::kForest);
	out.votes = static_cast<int>(votes);
	peaks_.votes = std::max(peaks_.votes, out.votes);
	return out;
}

size_t HoughVoter::walkParts(const ObjectModel &model, int first, int last, std::span<float> hist,
			     std::span<CastVote> out) const
{
	const ModelParams &params = model.params();
	const VoteBuffers &buffers = workspace_.votes();
	size_t n = 0;
	for (int i = first; i < last; ++i) {
		const Part &p = buffers.parts[static_cast<size_t>(i)];
		std::span<const PartCp> cps(buffers.pool.data() + p.cpOffset, p.cpCount);
		n = castPartVotes(model.forest(), cps, p.centreCamera, params.hocp, params.depthCheckMarginMm, hist, out,
				  n);
	}
	return n;
}

// Several threads: each walks a contiguous share of the parts into its share
// of the vote buffer, and the shares are then joined in part order: the
// votes of one thread, unless a share filled up (then one thread again,
// which truncates where one thread always did).
size_t HoughVoter::castVotes(const ObjectModel &model, int partCount)
{
	VoteBuffers &buffers = workspace_.votes();
	const std::span<CastVote> votes = buffers.votes;
	const size_t histSize = kMaxHistogramSlots * static_cast<size_t>(model.forest().dims);
	WorkerPool &workers = workspace_.workers();
	const int threads = workers.threads();
	if (threads > 1 && partCount >= 2 * threads && buffers.hist.size() >= histSize * static_cast<size_t>(threads)) {
		const size_t share = votes.size() / static_cast<size_t>(threads);
		std::array<size_t, WorkerPool::kMaxThreads> counts{};
		workers.run(threads, [&](int c, int thread) {
			counts[static_cast<size_t>(c)] =
				walkParts(model, partCount * c / threads, partCount * (c + 1) / threads,
					  buffers.hist.subspan(static_cast<size_t>(thread) * histSize, histSize),
					  votes.subspan(static_cast<size_t>(c) * share, share));
		});
		const bool joined =
			std::all_of(counts.begin(), counts.begin() + threads, [&](size_t n) { return n < share; });
		if (joined) {
			size_t total = counts[0]; // the first share is in place
			for (int c = 1; c < threads; ++c) {
				const auto from = votes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(c) * share);
				std::copy(from, from + static_cast<std::ptrdiff_t>(counts[static_cast<size_t>(c)]),
					  votes.begin() + static_cast<std::ptrdiff_t>(total));
				total += counts[static_cast<size_t>(c)];
			}
			return total;
		}
	}
	return walkParts(model, 0, partCount, buffers.hist.first(histSize), votes);
}

std::span<const PoseMode> HoughVoter::findModes(int count, const VoteModeConfig &config, size_t maxModes)
{
	VoteBuffers &b = workspace_.votes();
	VoteModeConfig c = config;
	c.maxSeeds = static_cast<int>(b.seeds.size());
	const size_t n = findPoseModes(votes(count), c,
				       {b.modeScratch, b.seeds, b.modeSupport, b.modePacked, &workspace_.workers(),
					b.modeThreadScratch, b.modeThreadSupport},
				       b.modes.first(std::min(maxModes, b.modes.size())));
	timer_.lap(Stage::kModes);
	return std::span<const PoseMode>(b.modes.data(), n);
}

std::optional<UnitCubeFrame> hypothesisFrame(BoxScorer &scorer, const Pose &pose)
{
	Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
	Eigen::Vector3f hi = -lo;
	if (!scorer.forEachShownPoint(pose, [&](const Eigen::Vector3d &point) {
		    const Eigen::Vector3f p = point.cast<float>();
		    lo = lo.cwiseMin(p);
		    hi = hi.cwiseMax(p);
	    }))
		return std::nullopt;
	if (!(hi.x() >= lo.x()))
		return std::nullopt;
	UnitCubeFrame frame;
	frame.centre = 0.5f * (lo + hi);
	frame.alpha = std::max((hi - lo).maxCoeff(), 1.0f);
	frame.scale = 1.0f;
	return frame;
}

Hypothesis scoreModes(std::span<const PoseMode> modes, int iteration, BoxScorer &scorer, CandidatePool &pool)
{
	Hypothesis best;
	// Scored side by side on the pool's threads, then kept in mode order.
	constexpr size_t kRound = 32;
	Pose poses[kRound];
	HypothesisScore scores[kRound];
	for (size_t m = 0; m < modes.size(); ++m) {
		const size_t k = m % kRound;
		if (k == 0) {
			const size_t n = std::min(kRound, modes.size() - m);
			for (size_t j = 0; j < n; ++j) {
				poses[j].R = modes[m + j].rotation.toRotationMatrix().cast<double>();
				poses[j].t = modes[m + j].centre.cast<double>();
			}
			scorer.scoreAll(std::span<const Pose>(poses, n), std::span<HypothesisScore>(scores, n));
		}
		Hypothesis h;
		h.pose = poses[k];
		if (h.pose.t.z() <= 0)
			continue;
		h.score = scores[k];
		h.origin = iteration == 0 ? HypothesisOrigin::kRegistration : HypothesisOrigin::kRefinement;
		h.iteration = iteration;
		h.valid = true;
		pool.report(h, "mode", static_cast<int>(m), modes[m].rotationDensity);
		pool.keep(h);
		if (!best.valid || h.score.score > best.score.score)
			best = h;
	}
	return best;
}

} // namespace ihf
