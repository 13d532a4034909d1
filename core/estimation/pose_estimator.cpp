// SPDX-License-Identifier: MIT
#include "core/estimation/pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/estimation/warm_up_scene.h"

namespace ihf {

namespace {

// What the window's box says about the object's place: a side on the frame
// border was clipped, so that axis' centre is not the object's, and the
// model may go on past that side unseen.
BoxAxes boxAxes(const OpenSides &open)
{
	return BoxAxes{!open.left && !open.right, !open.top && !open.bottom, open};
}

// The mode finder's settings for votes cast with voteCfg.
VoteModeConfig voteModeConfig(const EstimatorConfig &config, const EstimatorConfig &voteCfg, double diameter)
{
	VoteModeConfig modes;
	modes.translationBandwidth = static_cast<float>(config.translationBandwidth * diameter);
	modes.rotationBandwidth = config.rotationBandwidthDeg * static_cast<float>(M_PI / 180.0);
	modes.rotationModesPerCentre = std::max(1, config.rotationModes);
	modes.maxShiftVotes = voteCfg.maxShiftVotes;
	return modes;
}

} // namespace

size_t PoseEstimator::arenaBytes(const EstimatorLimits &limits)
{
	return EstimatorWorkspace::arenaBytes(limits);
}

PoseEstimator::PoseEstimator(const EstimatorLimits &limits, const Clock *clock)
	: workspace_(limits), planner_(clock)
{
	workspace_.attachPool(pool_);
}

void PoseEstimator::beginFrame(int boxes, float budgetMs)
{
	planner_.beginFrame(boxes, budgetMs);
}

void PoseEstimator::endFrame()
{
	// The frame ends with its last box's last stage.
	planner_.endFrame(timer_.last());
}

PoseEstimator::BoxScope::BoxScope(PoseEstimator &e, const EstimatorConfig &config)
	: e_(e), scratch_(e.workspace_.arena()), ownFrame_(!e.planner_.inFrame())
{
	if (ownFrame_)
		e_.beginFrame(1, config.frameBudgetMs);
	e_.planner_.beginBox();
}

PoseEstimator::BoxScope::~BoxScope()
{
	// The box ends with its last stage (what follows it is bookkeeping).
	const int64_t now = e_.planner_.endBox();
	if (ownFrame_)
		e_.planner_.endFrame(now);
	e_.workspace_.endBox();
}

EstimatorStats PoseEstimator::stats() const
{
	EstimatorStats s;
	const BudgetCounters &c = planner_.counters();
	const FrameBudget &frame = planner_.frame();
	s.stages = timer_.counters();
	s.frames = frame.frames();
	s.boxes = frame.boxes();
	s.iterations = c.iterations;
	s.budgetStops = c.budgetStops;
	s.icpSkipped = c.icpSkipped;
	s.researches = research_.rounds();
	s.researchWins = research_.wins();
	s.researchesSkipped = c.researchesSkipped;
	s.registrationOverruns = c.registrationOverruns;
	s.tightBoxes = c.tightBoxes;
	s.shortBoxes = c.shortBoxes;
	s.leanSearchBoxes = c.leanSearchBoxes;
	s.frameOverruns = frame.frameOverruns();
	s.boxOverruns = frame.boxOverruns();
	s.worstFrameNs = frame.worstFrameNs();
	s.arenaCapacity = workspace_.arena().capacity();
	s.arenaPersistent = workspace_.persistentBytes();
	s.arenaHighWater = workspace_.arena().highWater();
	s.peaks = peaks_;
	return s;
}

PoseEstimate PoseEstimator::estimate(ImageView<const float> depth, const CameraIntrinsics &K,
				     const PixelBox &box, const ObjectModel &model,
				     const EstimatorConfig &requested)
{
	PoseEstimate out;
	BoxScope scope(*this, requested);
	EstimatorConfig budgeted;
	const EstimatorConfig &config = boxSettings(requested, budgeted);

	// The box as a virtual on-axis crop, its scorer and polisher.
	VirtualCrop crop;
	if (const char *why = startBox(depth, K, box, model, config, crop)) {
		out.reason = why;
		return out;
	}
	const double diameter = model.params().diameter;
	BoxScorer scorer(workspace_,
			 ScoreWindow{workspace_.observed(), crop.intrinsics, openSides_, &config.score, crop.downsample},
			 model);
	HypothesisPolisher polisher(workspace_, voter_, timer_, scorer, config);
	PartWindow parts(workspace_, model, scorer.window(), crop.validPixels);
	pool_.beginBox(crop.rotation, diameter, config.iterations);
	ProposalBox proposals{config, model, boxAxes(openSides_), boundingBox(model.mesh()).centre().cast<double>(),
			      requested.iterations, findSlabs(config, diameter), workspace_, scorer, pool_, polisher,
			      planner_, parts};
	if (symmetryTurns_.enabled(proposals))
		comparePartsAtFullWindow(proposals, depth, K, box, crop.downsample);
	planAfterPasses(proposals);

	// The initial registration's votes, then k refinement iterations.
	Hypothesis forestBests[2];
	voteAndRefine(proposals, polisher, forestBests, out);
	if (pool_.empty()) {
		out.reason = "no vote mode (no parts could be described)";
		return out;
	}

	// Proposals the votes did not give, kept with theirs.
	if (views_.enabled(proposals))
		views_.propose(proposals, {}, {});
	out.budgetStopped = planner_.boxCut();

	// The best distinct hypotheses polished; the best polished one wins.
	Hypothesis best = pool_.best();
	Polished polished;
	polishCandidates(proposals, forestBests, polished, best, out);

	// Proposals at the polished best.
	if (polished.candidates > 0 && research_.enabled(proposals)) {
		out.icpApplied |= takeBetter(best, research_.propose(proposals, best, polished.items()));
		out.researches = research_.lastRounds();
		out.budgetStopped = out.budgetStopped || planner_.boxCut();
	}
	if (halfTurns_.enabled(proposals))
		out.icpApplied |= takeBetter(best, halfTurns_.propose(proposals, best, polished.items()));
	// A nearly symmetric object: the turn the depth prefers where the two
	// differ wins, whatever the whole-silhouette scores.
	symmetryTurns_.clear();
	if (symmetryTurns_.enabled(proposals)) {
		const Hypothesis chosen = symmetryTurns_.propose(proposals, best, polished.items());
		if (chosen.valid && symmetryTurns_.verdict().turned) {
			best = chosen;
			out.icpApplied = true;
		}
		out.budgetStopped = out.budgetStopped || planner_.boxCut();
	}

	finish(proposals, crop.rotation, best, out);
	return out;
}

void PoseEstimator::comparePartsAtFullWindow(ProposalBox &box, ImageView<const float> depth,
					     const CameraIntrinsics &K, const PixelBox &pixelBox, int downsample)
{
	// Cropped at the limit already (unbudgeted): a crop again would be the same.
	if (boxWindowBuffer(box.config).size() >= workspace_.partCropBuffer().size())
		return;
	box.parts.cropFiner(depth, K, pixelBox, downsample, limits().maxWindowPixels);
	timer_.lap(Stage::kCrop);
	if (box.config.budgetScaleByBox)
		planner_.setStageWork(Stage::kSymmetryTurns, std::max(1, box.parts.validPixels()));
}

const EstimatorConfig &PoseEstimator::boxSettings(const EstimatorConfig &requested, EstimatorConfig &budgeted)
{
	if (planner_.unlimited())
		return requested;
	const ShareSettings share = underShare(requested, planner_.shareMs());
	budgeted = share.config;
	planner_.counters().tightBoxes += share.tight;
	planner_.counters().shortBoxes += share.shortRounds;
	if (planner_.chooseLeanSearch(static_cast<double>(requested.views.leanSearchBelow)))
		budgeted.views = underLeanBudget(requested.views);
	return budgeted;
}

std::span<float> PoseEstimator::boxWindowBuffer(const EstimatorConfig &config)
{
	std::span<float> window = workspace_.cropBuffer();
	if (config.windowPixels > 0 && static_cast<size_t>(config.windowPixels) < window.size())
		window = window.first(static_cast<size_t>(config.windowPixels));
	return window;
}

const char *PoseEstimator::startBox(ImageView<const float> depth, const CameraIntrinsics &K, const PixelBox &box,
				    const ObjectModel &model, const EstimatorConfig &config, VirtualCrop &crop)
{
	if (!workspace_.valid())
		return "estimator has no memory (arena allocation failed)";
	if (model.renderMesh().vertices.size() > workspace_.renderCapacity())
		return "model mesh larger than the estimator's render limit";
	if (model.forest().dims > limits().maxHistogramDims)
		return "forest histogram longer than the estimator's limit";
	workspace_.setCulling(config.cullBackFaces && model.renderMeshClosed());
	const CropStatus status = makeVirtualCrop(depth, K, box, boxWindowBuffer(config), crop);
	timer_.lap(Stage::kCrop);
	if (status != CropStatus::kOk)
		return status == CropStatus::kOutsideImage ? "box outside the image" : "empty box";
	if (crop.validPixels < config.minValidPixels)
		return "too few valid depth pixels in the box";
	planner_.setBoxWork(config.budgetScaleByBox ? std::max(1, crop.validPixels) : 1);
	openSides_ = openSidesOf(box.x, box.y, box.w, box.h, depth.width, depth.height);
	const int w = crop.intrinsics.width, h = crop.intrinsics.height;
	peaks_.windowPixels = std::max(peaks_.windowPixels, w * h);
	if (!workspace_.beginBox(w, h))
		return "arena too small for the box";
	workspace_.maskAll();
	return nullptr;
}

// The view search's depth centres use the slabs too (at least as many as it
// asks for), whether or not the registration votes per slab.
size_t PoseEstimator::findSlabs(const EstimatorConfig &config, double diameter)
{
	const size_t wanted = static_cast<size_t>(std::max(config.depthWindows, config.views.depthCentres));
	if (wanted == 0)
		return 0;
	SlabBuffers &slabs = workspace_.slabs();
	return findDepthWindows(workspace_.observed(), static_cast<float>(config.depthWindowWidth * diameter), slabs.hist,
				slabs.windows.first(std::min(slabs.windows.size(), wanted)));
}

// What the box runs after its vote passes, for the planner's passFits():
// the searches at the voted centres and the dense slabs (not the thinner
// slabs the search may add), the polish rounds, and the re-search with its
// rounds.
void PoseEstimator::planAfterPasses(const ProposalBox &box)
{
	const EstimatorConfig &config = box.config;
	const bool research = research_.enabled(box);
	int searches = 0;
	if (views_.enabled(box))
		searches = votedCentres(config) +
			   static_cast<int>(std::min(box.slabs, static_cast<size_t>(std::max(0, config.views.depthCentres)))) +
			   research;
	int rounds = 0;
	if (config.icp)
		rounds = std::max(1, box.polisher.rounds(static_cast<size_t>(std::max(0, config.icpCandidates)))) +
			 (research ? box.polisher.rounds(researchPolished(config)) : 0);
	// A nearly symmetric object's comparison of its turns comes last and
	// is what places its part: its time is kept from the passes and
	// searches before it.
	const SymmetryRivalSource::KeptTime kept = symmetryTurns_.keptTime(box);
	planner_.plan(searches, rounds, Stage::kSymmetryTurns, kept.runs, kept.polishRounds);
}

// Eq. 10: each refinement sees only the crop inside the previous
// iteration's best hypothesis' depth range, normalised with the unit cube
// of that whole rendered hypothesis (EstimatorConfig::hypothesisCube).
void PoseEstimator::voteAndRefine(ProposalBox &box, HypothesisPolisher &polisher, Hypothesis (&bests)[2],
				  PoseEstimate &out)
{
	const EstimatorConfig &config = box.config;
	// Refinement iterations vote leaner (the iteration* bounds).
	const EstimatorConfig iterationCfg = forIterations(config);
	std::optional<UnitCubeFrame> cube;
	for (int k = 0; k <= config.iterations; ++k) {
		if (k > 0 && !planner_.passFits(config.budgetMargin)) {
			out.budgetStopped = true;
			break;
		}
		const Hypothesis best = voteIteration(box, k, k > 0 ? iterationCfg : config, cube ? &*cube : nullptr, out);
		if (!best.valid)
			break;
		out.iterationsDone = k;
		bests[k == 0 ? 0 : 1] = best;
		if (k < config.iterations) {
			polisher.maskToHypothesis(best.score);
			cube = config.hypothesisCube ? hypothesisFrame(box.scorer, best.pose) : std::nullopt;
			timer_.resume(Stage::kScore); // the hypothesis' render for its cube
		}
	}
}

Hypothesis PoseEstimator::voteIteration(ProposalBox &box, int k, const EstimatorConfig &voteCfg,
					 const UnitCubeFrame *cube, PoseEstimate &out)
{
	const EstimatorConfig &config = box.config;
	const ModelParams &params = box.model.params();
	const CameraIntrinsics &vk = box.scorer.intrinsics();
	const VoteModeConfig modeCfg = voteModeConfig(config, voteCfg, params.diameter);
	const size_t maxModes =
		static_cast<size_t>(std::max(1, config.maxHypotheses)) * static_cast<size_t>(modeCfg.rotationModesPerCentre);
	// The registration votes once per dense depth slab (or once on the
	// whole box); a refinement once on the masked crop.
	const size_t slabs = std::min(box.slabs, static_cast<size_t>(std::max(0, config.depthWindows)));
	const size_t passes = k == 0 ? std::max<size_t>(1, slabs) : 1;
	const StageTotals iterationStart = timer_.totals();
	Hypothesis best;
	for (size_t pass = 0; pass < passes; ++pass) {
		// The first slab always runs (every box gets a pose); a further one
		// only if a pass still fits, with room for the searches and the
		// polish after it (as for an iteration).
		if (pass > 0 && !planner_.passFits(config.budgetMargin)) {
			out.budgetStopped = true;
			break;
		}
		if (k == 0 && slabs > 0)
			workspace_.maskToRange(workspace_.slabs().windows[pass].nearMm, workspace_.slabs().windows[pass].farMm);
		const int points = voter_.buildCloud(workspace_.working(), vk, params);
		if (points < config.minValidPixels)
			continue;
		const VoteCount votes = voter_.vote(vk, box.model, voteCfg, points, k > 0 ? cube : nullptr);
		out.parts = votes.parts;
		out.votes = votes.votes;
		if (votes.votes == 0)
			continue;
		pool_.reportVotes(k, static_cast<int>(pass), voter_.votes(votes.votes));
		const std::span<const PoseMode> modes = voter_.findModes(votes.votes, modeCfg, maxModes);
		const Hypothesis h = scoreModes(modes, k, box.scorer, pool_);
		timer_.lap(Stage::kScore);
		takeBetter(best, h);
	}
	// The registration's passes are observed together: an over-estimate of
	// one refinement, which keeps the budget safe.
	planner_.observePass(iterationStart, k > 0);
	if (k == 0)
		planner_.endRegistration();
	return best;
}

// Each candidate is polished by ICP on the crop cut to its own depth range.
// Candidates are polished in rounds, one per pool thread (each polish on its
// own slot), and their results taken in candidate order as one thread
// would; the budget is checked before each round. The best polished
// candidate replaces `best` (the pool's best as proposed) even where that
// proposal scored higher: the best of many guesses, each placed by a
// sparse fit, is the one whose score luck raised most, while a polished
// pose has settled where the depth holds it. Where the budget polished
// none, the proposal stands.
void PoseEstimator::polishCandidates(ProposalBox &box, const Hypothesis (&forestBests)[2], Polished &polished,
				     Hypothesis &best, PoseEstimate &out)
{
	const EstimatorConfig &config = box.config;
	if (!config.icp)
		return;
	FixedList<Hypothesis, kMaxPolished> candidates;
	pool_.polishCandidates({config.icpCandidates, config.polishRegistration, config.polishForestBests},
			       forestBests[0], forestBests[1], candidates);
	polished.candidates = candidates.size();
	const size_t round = static_cast<size_t>(box.polisher.threads());
	Hypothesis icped[kMaxPolished];
	Hypothesis polishedBest;
	bool bestIcped = false;
	for (size_t c0 = 0; c0 < candidates.size(); c0 += round) {
		if (!planner_.polishFits(config.budgetMargin)) {
			out.icpSkipped = true;
			break;
		}
		const int64_t icpStart = timer_.last();
		const size_t n = std::min(round, candidates.size() - c0);
		box.polisher.polishAll(candidates.items().subspan(c0, n), std::span<Hypothesis>(icped + c0, n), Stage::kIcp);
		for (size_t c = c0; c < c0 + n; ++c) {
			polished.results[c] = icped[c].valid ? icped[c] : candidates[c];
			if (icped[c].valid)
				pool_.report(icped[c], "icp", static_cast<int>(c));
			if (takeBetter(polishedBest, polished.results[c]))
				bestIcped = icped[c].valid;
		}
		polished.count = c0 + n;
		// The cost model sees the whole round (its clouds are counted
		// under the cloud stage on one thread, under ICP on more).
		planner_.observePolish(icpStart);
	}
	if (polishedBest.valid) {
		best = polishedBest;
		out.icpApplied = bestIcped;
	}
}

// The confidence: the score, less when a distinct rival scored nearly as
// well (rival_poses.h); symmetric objects' rivals are compared by the
// model's box centre.
void PoseEstimator::finish(const ProposalBox &box, const Eigen::Matrix3d &cropRotation, const Hypothesis &best,
			   PoseEstimate &out) const
{
	const ModelParams &params = box.model.params();
	out.bestIteration = pool_.reportedIteration(best);
	out.found = true;
	out.pose.R = cropRotation * best.pose.R;
	out.pose.t = cropRotation * best.pose.t;
	out.score = best.score;
	const double distinctMm = box.config.confidence.distinctShare * params.diameter;
	const float rival = pool_.bestDistinctRival(best.pose, box.model.mesh().vertices, box.modelCentre,
						    params.symmetric, distinctMm);
	out.margin = std::max(0.0f, best.score.score - rival);
	// A nearly symmetric object's rivals are its turns, which score alike
	// whether or not the part that tells them apart is seen: the pixels
	// where they differ decide. Beaten there by the best, they are no
	// rivals; undecided, the pose is ambiguous.
	const SymmetryVerdict &sym = symmetryTurns_.verdict();
	if (sym.ran && sym.decisive)
		out.margin = std::max(out.margin, box.config.confidence.fullMargin);
	out.confidence = poseConfidence(best.score.score, out.margin, box.config.confidence);
	if (sym.ran && sym.ambiguous) {
		out.ambiguous = true;
		out.ambiguityAxis = (out.pose.R * sym.axis).normalized();
		out.confidence *= box.config.symmetryTurns.ambiguousConfidence;
	}
}

Expected<HypothesisScore> PoseEstimator::scorePose(ImageView<const float> depth, const CameraIntrinsics &K,
						   const PixelBox &box, const ObjectModel &model,
						   const EstimatorConfig &config, const Pose &pose)
{
	if (!workspace_.valid())
		return makeError(Errc::kCapacity, "estimator has no memory (arena allocation failed)");
	if (model.renderMesh().vertices.size() > workspace_.renderCapacity())
		return makeError(Errc::kCapacity, "model mesh larger than the estimator's render limit");
	ArenaScope scratch(workspace_.arena());
	VirtualCrop crop;
	const CropStatus status = makeVirtualCrop(depth, K, box, workspace_.cropBuffer(), crop);
	if (status == CropStatus::kOutsideImage)
		return makeError(Errc::kInvalidArgument, "box outside the image");
	if (status != CropStatus::kOk)
		return makeError(Errc::kInvalidArgument, "empty box");
	const CameraIntrinsics &vk = crop.intrinsics;
	openSides_ = openSidesOf(box.x, box.y, box.w, box.h, depth.width, depth.height);
	if (!workspace_.beginBox(vk.width, vk.height))
		return makeError(Errc::kCapacity, "arena too small for the box");
	Pose virt;
	virt.R = crop.rotation.transpose() * pose.R;
	virt.t = crop.rotation.transpose() * pose.t;
	BoxScorer scorer(workspace_, ScoreWindow{workspace_.observed(), vk, openSides_, &config.score, crop.downsample},
			 model);
	const HypothesisScore s = scorer.score(virt);
	workspace_.endBox();
	return s;
}

Expected<WarmUpCost> PoseEstimator::warmUp(const ObjectModel &model, const CameraIntrinsics &K,
					    const EstimatorConfig &config)
{
	if (!workspace_.valid())
		return makeError(Errc::kCapacity, "estimator has no memory (arena allocation failed)");
	workspace_.setCulling(config.cullBackFaces && model.renderMeshClosed());
	auto scene = makeWarmUpScene(model, K, limits().maxWindowPixels, workspace_.renderer());
	if (!scene)
		return scene.error();

	// The box runs as a frame's only box would: its share is the frame
	// (an unlimited frame: no share profile).
	const ShareSettings share =
		underShare(config, config.frameBudgetMs > 0 ? static_cast<double>(config.frameBudgetMs)
							    : std::numeric_limits<double>::infinity());
	EstimatorConfig c = share.config;
	c.frameBudgetMs = 0;
	EstimateObserver *observer = pool_.observer();
	pool_.setObserver(nullptr);
	beginFrame(1, 0);
	const PoseEstimate e = estimate(scene->depth.view(), K, scene->box, model, c);
	endFrame();
	pool_.setObserver(observer);

	WarmUpCost cost;
	cost.registrationMs = static_cast<double>(planner_.registrationNs()) * 1e-6;
	cost.boxMs = static_cast<double>(planner_.frame().worstFrameNs()) * 1e-6;
	cost.tight = share.tight;
	cost.parts = e.parts;

	planner_.forgetCounts();
	research_.forgetCounts();
	peaks_ = {};
	if (!e.found)
		return makeError(Errc::kNoPose, std::string("warm-up box gave no pose: ") + e.reason);
	return cost;
}

} // namespace ihf
