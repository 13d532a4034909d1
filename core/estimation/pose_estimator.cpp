// SPDX-License-Identifier: MIT
#include "core/estimation/pose_estimator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "core/estimation/forest_walker.h"
#include "core/estimation/icp_polisher.h"
#include "core/estimation/virtual_crop.h"
#include "core/features/depth_cloud.h"
#include "core/features/part_units.h"
#include "core/features/unit_cube_frame.h"

namespace ihf {

namespace {

// Voted translations a box searches at most (ViewSearchConfig::centres).
constexpr int kMaxViewCentres = 4;

// Proposals a view search returns (ViewSearchConfig::keep).
size_t viewKeep(const EstimatorConfig &config)
{
	return static_cast<size_t>(std::clamp(config.views.keep, 1, kMaxViewKeep));
}

// Voted translations searched (ViewSearchConfig::centres), at most.
int votedCentres(const EstimatorConfig &config)
{
	return std::clamp(config.views.centres, 1, kMaxViewCentres);
}

// Proposals of a re-search round that are polished.
size_t researchPolished(const EstimatorConfig &config)
{
	return std::min(viewKeep(config), static_cast<size_t>(std::max(0, config.researchPolish)));
}

// Refinement's re-search rounds (none at k = 0): at most the requested k,
// whatever the budget's bound on the iterations; none without the view
// search.
int researchRounds(const EstimatorConfig &config, int requestedIterations, const ObjectModel &model)
{
	if (!(viewSearchSize(model.viewTemplates(), config.views) > 0))
		return 0;
	return std::max(0, std::min(config.researchRounds, requestedIterations));
}

// Two hypotheses are one when within sameTranslationMm and 10 deg.
bool samePose(const Pose &a, const Pose &b, double sameTranslationMm)
{
	constexpr double kSameRotation = 10.0 * M_PI / 180.0;
	return (a.t - b.t).norm() < sameTranslationMm && rotationAngle(a.R, b.R) < kSameRotation;
}

IbsLimits ibsLimits(const EstimatorLimits &limits)
{
	IbsLimits ibs;
	ibs.maxN = limits.maxIbsN;
	ibs.maxPoints = limits.maxIbsPoints;
	ibs.maxActive = limits.maxActive;
	ibs.threads = WorkerPool::resolve(limits.threads);
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

// Inserts h into top[0, n), kept sorted best first and at most keep long.
template <typename H>
void insertTop(const H &h, H *top, int &n, int keep)
{
	int pos = n;
	while (pos > 0 && top[pos - 1].score.score < h.score.score)
		--pos;
	if (pos >= keep)
		return;
	for (int j = std::min(n, keep - 1); j > pos; --j)
		top[j] = top[j - 1];
	top[pos] = h;
	n = std::min(n + 1, keep);
}

} // namespace

template<typename A>
bool PoseEstimator::carvePersistent(A &arena)
{
	const EstimatorLimits &l = limits_;
	return arenaTake(arena, observed_, count(l.maxWindowPixels)) &&
	       arenaTake(arena, active_, count(l.maxActive)) && arenaTake(arena, parts_, count(l.maxParts)) &&
	       arenaTake(arena, pool_, count(l.maxParts) * count(l.maxPartControlPoints)) &&
	       arenaTake(arena, hist_, kMaxHistogramSlots * count(l.maxHistogramDims) * WorkerPool::resolve(l.threads)) &&
	       arenaTake(arena, votes_, count(l.maxVotes)) &&
	       arenaTake(arena, modeScratch_, count(l.maxVotes)) &&
	       arenaTake(arena, modeSupport_, count(l.maxVotes)) &&
	       arenaTake(arena, modePacked_, count(l.maxVotes)) &&
	       arenaTake(arena, modeThreadScratch_, (WorkerPool::resolve(l.threads) - 1) * count(l.maxVotes)) &&
	       arenaTake(arena, modeThreadSupport_, (WorkerPool::resolve(l.threads) - 1) * count(l.maxVotes)) &&
	       arenaTake(arena, seeds_, count(l.maxModeSeeds)) && arenaTake(arena, modes_, count(l.maxModes)) &&
	       arenaTake(arena, windowHist_, size_t{1024}) && arenaTake(arena, windows_, size_t{8}) &&
	       arenaTake(arena, anchorWindows_, size_t{4}) &&
	       arenaTake(arena, viewHeaps_, viewSearchHeapSize(WorkerPool::resolve(l.threads))) &&
	       arenaTake(arena, viewFine_, size_t{kMaxCoarseKeep}) &&
	       arenaTake(arena, kept_, count(std::max(1, l.maxCandidates))) &&
	       arenaTake(arena, registrationKept_, count(std::max(1, l.maxCandidates))) &&
	       arenaTake(arena, rivalStore_, count(l.maxRivals));
}

template<typename A>
bool PoseEstimator::carveBox(A &arena, size_t pixels)
{
	// One render buffer, and for the other threads' polishes one mask and
	// one cloud, per pool thread.
	const size_t others = static_cast<size_t>(WorkerPool::resolve(limits_.threads) - 1);
	return arenaTake(arena, working_, pixels) && arenaTake(arena, render_, pixels * (others + 1)) &&
	       arenaTake(arena, moreWorking_, pixels * others) && arenaTake(arena, moreClouds_, pixels * others) &&
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
	       PartExtractor::arenaBytes(partLimits(limits)) +
	       DepthRenderer::arenaBytes(limits.maxMeshVertices) * static_cast<size_t>(WorkerPool::resolve(limits.threads));
}

PoseEstimator::PoseEstimator(const EstimatorLimits &limits, const Clock *clock, int)
	: limits_(limits), planner_(clock)
{
}

PoseEstimator::PoseEstimator(const EstimatorLimits &limits, const Clock *clock)
	: limits_(limits), workers_(limits.threads), planner_(clock)
{
	auto arena = Arena::create(arenaBytes(limits));
	if (!arena)
		return;
	arena_ = std::move(*arena);
	valid_ = fitter_.reserve(ibsLimits(limits), arena_).ok() &&
		 extractor_.reserve(partLimits(limits), arena_).ok() &&
		 renderer_.reserve(limits.maxMeshVertices, arena_).ok() && carvePersistent(arena_);
	for (int t = 1; t < workers_.threads() && valid_; ++t)
		valid_ = moreRenderers_[static_cast<size_t>(t - 1)].reserve(limits.maxMeshVertices, arena_).ok();
	rivals_ = RivalPoses(rivalStore_);
	persistentBytes_ = arena_.used();
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
	: e_(e), scratch_(e.arena_), ownFrame_(!e.planner_.inFrame())
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
	e_.releaseBox();
}

// Forgets the per-box spans; the arena scope that carved them rewinds.
void PoseEstimator::releaseBox()
{
	working_ = render_ = moreWorking_ = {};
	moreClouds_ = {};
	cloud_ = {};
	unit_ = normals_ = {};
}

// What the box runs after its vote passes, for the planner's passFits():
// the searches at the voted centres and the dense slabs (not the thinner
// slabs the search may add), the polish rounds, and the re-search with its
// rounds.
void PoseEstimator::planAfterPasses(const EstimatorConfig &config, int requestedIterations,
				    const ObjectModel &model)
{
	const bool views = viewSearchSize(model.viewTemplates(), config.views) > 0;
	const bool research = researchRounds(config, requestedIterations, model) > 0;
	int searches = 0;
	if (views)
		searches = votedCentres(config) +
			   static_cast<int>(std::min(windowCount_, static_cast<size_t>(std::max(
									   0, config.views.depthCentres)))) +
			   research;
	int rounds = 0;
	if (config.icp)
		rounds = std::max(1, polishRounds(static_cast<size_t>(std::max(0, config.icpCandidates)))) +
			 (research ? polishRounds(researchPolished(config)) : 0);
	planner_.plan(searches, rounds);
}

int PoseEstimator::polishRounds(size_t polishes) const
{
	const size_t threads = static_cast<size_t>(workers_.threads());
	return static_cast<int>((polishes + threads - 1) / threads);
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
	s.researches = researches_;
	s.researchWins = researchWins_;
	s.researchesSkipped = c.researchesSkipped;
	s.registrationOverruns = c.registrationOverruns;
	s.tightBoxes = c.tightBoxes;
	s.shortBoxes = c.shortBoxes;
	s.leanSearchBoxes = c.leanSearchBoxes;
	s.frameOverruns = frame.frameOverruns();
	s.boxOverruns = frame.boxOverruns();
	s.worstFrameNs = frame.worstFrameNs();
	s.arenaCapacity = arena_.capacity();
	s.arenaPersistent = persistentBytes_;
	s.arenaHighWater = arena_.highWater();
	s.peaks = peaks_;
	return s;
}

void PoseEstimator::report(int iteration, const char *stage, int rank, const Pose &virtualPose,
			   const HypothesisScore &s, float density)
{
	rivals_.add(virtualPose, s.score);
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
void PoseEstimator::keep(const Hypothesis &h, float sameTranslationMm, bool fromRefinement)
{
	keepIn(kept_, keptCount_, h, sameTranslationMm);
	if (!fromRefinement)
		keepIn(registrationKept_, registrationKeptCount_, h, sameTranslationMm);
}

void PoseEstimator::keepIn(std::span<Hypothesis> kept, size_t &count, const Hypothesis &h,
			   float sameTranslationMm)
{
	for (size_t i = 0; i < count; ++i) {
		Hypothesis &k = kept[i];
		if (samePose(k.pose, h.pose, sameTranslationMm)) {
			if (h.score.score <= k.score.score)
				return;
			// Remove it; the new one is inserted below.
			std::move(kept.begin() + i + 1, kept.begin() + count, kept.begin() + i);
			--count;
			break;
		}
	}
	size_t pos = 0;
	while (pos < count && kept[pos].score.score >= h.score.score)
		++pos;
	if (pos >= kept.size())
		return;
	if (count < kept.size())
		++count;
	std::move_backward(kept.begin() + pos, kept.begin() + count - 1, kept.begin() + count);
	kept[pos] = h;
}

// The distinct best hypotheses, then the forest's own bests after a
// refinement (the registration's and the last iteration's) when they are
// not among them: the view proposals outscore an unpolished forest mode
// that ICP would bring to the truth (syn200 bunny: a mode 11-17 deg off
// ranked below the 16 polished and was lost once refinement had added its
// modes to the ranking), so refinement never drops what the registration
// alone would have polished.
size_t PoseEstimator::polishCandidates(const EstimatorConfig &config, double diameter,
				       const Hypothesis (&forestBest)[2], std::span<Hypothesis> out) const
{
	const size_t wanted = static_cast<size_t>(std::max(0, config.icpCandidates));
	size_t n = std::min({keptCount_, wanted, out.size()});
	std::copy_n(kept_.begin(), n, out.begin());
	if (n == 0 || !forestBest[1].valid) // or no refinement ran
		return n;
	auto add = [&](const Hypothesis &h) {
		bool seen = !h.valid;
		for (size_t i = 0; i < n && !seen; ++i)
			seen = samePose(out[i].pose, h.pose, 0.05 * diameter);
		if (!seen && n < out.size())
			out[n++] = h;
	};
	if (config.polishRegistration)
		for (size_t i = 0; i < std::min(registrationKeptCount_, wanted); ++i)
			add(registrationKept_[i]);
	if (config.polishForestBests)
		for (const Hypothesis &f : forestBest)
			add(f);
	return n;
}

int PoseEstimator::keptCentres(double diameter, int max, Eigen::Vector3d *centres) const
{
	int nc = 0;
	for (size_t i = 0; i < keptCount_ && nc < max; ++i) {
		bool seen = false;
		for (int j = 0; j < nc; ++j)
			seen = seen || (centres[j] - kept_[i].pose.t).norm() < 0.1 * diameter;
		if (!seen)
			centres[nc++] = kept_[i].pose.t;
	}
	return nc;
}

namespace {

// The view search's settings with the score's weights: its sparse score
// ranks by the same rule as the full one.
ViewSearchConfig viewScoring(const EstimatorConfig &config)
{
	ViewSearchConfig vc = config.views;
	vc.outlierWeight = config.score.outlierWeight;
	vc.occludedWeight = config.score.occludedWeight;
	vc.residualWeight = config.score.residualWeight;
	return vc;
}

} // namespace

// A side on the frame border was clipped: that axis' centre is not the
// object's, and the model may go on past that side unseen.
BoxAxes PoseEstimator::boxAxes() const
{
	return BoxAxes{!openSides_.left && !openSides_.right, !openSides_.top && !openSides_.bottom, openSides_};
}

size_t PoseEstimator::searchScored(const CameraIntrinsics &K, const ObjectModel &model,
				   const EstimatorConfig &config, const Eigen::Vector3d &centre, float anchor,
				   const char *stage, std::span<Hypothesis> out)
{
	const ViewSearchConfig vc = viewScoring(config); // under a budget: underBudget()'s already
	ViewProposal top[kMaxViewKeep];
	const size_t keepN = std::min(out.size(), static_cast<size_t>(kMaxViewKeep));
	const size_t n = searchViews(model.viewTemplates(), vc, observedView_, K, centre,
				     std::span<ViewProposal>(top, keepN), boxAxes(), anchor, &workers_,
				     ViewSearchWorkspace{viewHeaps_, viewFine_});
	Pose poses[kMaxViewKeep];
	HypothesisScore scores[kMaxViewKeep];
	for (size_t j = 0; j < n; ++j)
		poses[j] = top[j].pose;
	scoreAll(std::span<const Pose>(poses, n), std::span<HypothesisScore>(scores, n), K, model, config);
	for (size_t j = 0; j < n; ++j) {
		Hypothesis &h = out[j];
		h.pose = top[j].pose;
		h.score = scores[j];
		h.iteration = config.iterations + 1;
		h.valid = true;
		report(h.iteration, stage, static_cast<int>(j), h.pose, h.score, top[j].score);
	}
	return n;
}

// Verifies every view-template rotation at each of the best distinct
// translations; the best proposals are scored in full and kept. Runs under
// the polish's budget check, one translation at a time.
void PoseEstimator::searchViewTemplates(const CameraIntrinsics &K, const ObjectModel &model,
					const EstimatorConfig &config)
{
	const double diameter = model.params().diameter;
	Eigen::Vector3d centres[kMaxViewCentres];
	const int nc = keptCentres(diameter, votedCentres(config), centres);
	const size_t keepN = viewKeep(config);
	const float same = static_cast<float>(0.05 * diameter);
	// One search; its proposals are kept.
	auto searchAt = [&](const Eigen::Vector3d &centre, float anchor, const char *stage) {
		const int64_t start = timer_.last();
		Hypothesis found[kMaxViewKeep];
		const size_t n = searchScored(K, model, config, centre, anchor, stage,
					      std::span<Hypothesis>(found, keepN));
		for (size_t j = 0; j < n; ++j)
			keep(found[j], same);
		planner_.observeSearch(start);
	};
	// Under a budget every search but the first leaves room for the polish
	// after it (unbudgeted, everything fits). A box with no room for even
	// one search eases the search's prediction (StageCostModel::refused()):
	// else a cost once measured too high would keep the search out of
	// every later box (a 10 ms run of 200 boxes searched in none).
	int searched = 0;
	auto searchFits = [&]() {
		const bool first = searched++ == 0;
		const bool fits =
			planner_.searchFits(config.budgetMargin, config.icp && !first ? config.views.budgetPolishRounds : 0);
		if (!fits && first)
			planner_.searchRefused();
		return fits;
	};
	// Centres from the box and the depth alone: on the box's ray (the
	// virtual crop's optical axis) at each dense slab's median depth: the
	// registration's slabs, then thinner ones of the search's own whose
	// medians lie in front of all those (a large object's surface and the
	// wall behind it share a thick slab, whose median lies between them;
	// a thin slab behind is background, and more centres are more wrong
	// poses that can outscore the right one).
	constexpr size_t kMaxAnchors = 8;
	float anchors[kMaxAnchors];
	size_t na = 0;
	const size_t wanted = static_cast<size_t>(std::max(0, config.views.depthCentres));
	for (const DepthWindow &slab : windows_.first(std::min(windowCount_, wanted))) {
		const float a = windowMedianDepth(observedView_, slab, config.views.anchorShare);
		if (a > 0 && na < kMaxAnchors)
			anchors[na++] = a;
	}
	if (config.views.depthCentreWidth > 0 && wanted > 0) {
		const size_t thin = findDepthWindows(observedView_,
						     static_cast<float>(config.views.depthCentreWidth * diameter),
						     windowHist_, anchorWindows_.first(std::min(anchorWindows_.size(), wanted)));
		// Within half the search's depth alignment of one already
		// searched, a centre adds nothing.
		const float apart = 0.5f * config.views.maxShiftMm;
		float front = std::numeric_limits<float>::max();
		for (size_t j = 0; j < na; ++j)
			front = std::min(front, anchors[j]);
		const size_t thick = na;
		for (const DepthWindow &slab : anchorWindows_.first(thin)) {
			const float a = windowMedianDepth(observedView_, slab, config.views.anchorShare);
			bool seen = !(a > 0) || a > front - apart;
			for (size_t j = thick; j < na && !seen; ++j)
				seen = std::abs(a - anchors[j]) < apart;
			if (!seen && na < kMaxAnchors)
				anchors[na++] = a;
		}
	}
	// Each returns false when a search no longer fits (and the rest are off).
	auto voted = [&]() {
		for (int c = 0; c < nc; ++c) {
			if (!searchFits())
				return false;
			searchAt(centres[c], 0.0f, "view");
		}
		return true;
	};
	auto fromDepth = [&]() {
		for (size_t j = 0; j < na; ++j) {
			if (!searchFits())
				return false;
			searchAt(Eigen::Vector3d::Zero(), anchors[j], "view_depth");
		}
		return true;
	};
	if (config.views.depthFirst) {
		if (fromDepth())
			voted();
	} else if (voted()) {
		fromDepth();
	}
}

PoseEstimator::Hypothesis PoseEstimator::researchAtBest(const CameraIntrinsics &K, const ObjectModel &model,
							const EstimatorConfig &config, const Hypothesis &best,
							int maxRounds, int &rounds)
{
	const size_t keepN = viewKeep(config);
	const size_t polishN = researchPolished(config);
	const size_t round = static_cast<size_t>(workers_.threads());
	const double same = 0.05 * model.params().diameter;
	Hypothesis winner = best;
	for (rounds = 0; rounds < maxRounds;) {
		// The search and its polish rounds must fit.
		if (!planner_.researchFits(config.budgetMargin, config.icp ? polishRounds(polishN) : 0))
			break;
		++rounds;
		++researches_;
		const int64_t start = timer_.last();
		Hypothesis found[kMaxViewKeep];
		const size_t n = searchScored(K, model, config, winner.pose.t, 0.0f, "research",
					      std::span<Hypothesis>(found, keepN));
		planner_.observeSearch(start);
		// Every proposal competes; those that are not the best itself,
		// best first (as the search returns them), are polished in rounds
		// of the pool's threads.
		Hypothesis fresh[kMaxViewKeep], polished[kMaxViewKeep];
		Hypothesis roundBest;
		size_t m = 0;
		for (size_t j = 0; j < n; ++j) {
			if (!roundBest.valid || found[j].score.score > roundBest.score.score)
				roundBest = found[j];
			if (m < polishN && !samePose(found[j].pose, winner.pose, same))
				fresh[m++] = found[j];
		}
		for (size_t c0 = 0; config.icp && c0 < m; c0 += round) {
			const int64_t icpStart = timer_.last();
			const size_t k = std::min(round, m - c0);
			workers_.run(static_cast<int>(k), [&](int i, int slot) {
				const size_t c = c0 + static_cast<size_t>(i);
				polished[c] = polishOn(fresh[c], K, model, config, Stage::kIcp, slot, config.icpConfig);
			});
			planner_.observePolish(icpStart);
			for (size_t c = c0; c < c0 + k; ++c) {
				if (!polished[c].valid)
					continue;
				report(polished[c].iteration, "research_icp", static_cast<int>(c), polished[c].pose,
				       polished[c].score, 0);
				if (polished[c].score.score > roundBest.score.score)
					roundBest = polished[c];
			}
		}
		if (!roundBest.valid || roundBest.score.score <= winner.score.score)
			break;
		winner = roundBest;
		++researchWins_;
	}
	return winner;
}

PoseEstimator::Hypothesis PoseEstimator::polishIcp(const Hypothesis &h, const CameraIntrinsics &K,
						   const ObjectModel &model, const EstimatorConfig &config,
						   Stage stage, const IcpConfig &icp)
{
	// What ran before is the caller's stage, the cloud the cloud's, the
	// rest ICP's; the caller's lap counts the call.
	timer_.resume(stage);
	maskToHypothesis(h.score, config);
	const int n = buildCloud(workingView_, K, model.params());
	Hypothesis out = icpAndScore(h, cloud_.first(static_cast<size_t>(n)), K, model, config, 0, icp);
	timer_.resume(Stage::kIcp);
	return out;
}

PoseEstimator::Hypothesis PoseEstimator::fromPolish(const PolishResult &polished, int iteration)
{
	Hypothesis out;
	if (polished.valid) {
		out.pose = polished.pose;
		out.score = polished.score;
		out.iteration = iteration;
		out.valid = true;
	}
	return out;
}

PoseEstimator::Hypothesis PoseEstimator::icpAndScore(const Hypothesis &h, std::span<const CloudPoint> cloud,
						     const CameraIntrinsics &K, const ObjectModel &model,
						     const EstimatorConfig &config, int slot, const IcpConfig &icpConfig)
{
	const PolishResult polished =
		polishFromCloud(scoreWindow(K, config), model, h.pose, cloud, icpConfig, rendererOf(slot), renderViewOf(slot));
	return fromPolish(polished, h.iteration);
}

PoseEstimator::Hypothesis PoseEstimator::polishOn(const Hypothesis &h, const CameraIntrinsics &K,
						  const ObjectModel &model, const EstimatorConfig &config, Stage stage,
						  int slot, const IcpConfig &icp)
{
	// One thread: the stage counters see the cloud apart.
	return workers_.threads() == 1 ? polishIcp(h, K, model, config, stage, icp)
				       : polishIcpIn(h, K, model, config, slot, icp);
}

PoseEstimator::Hypothesis PoseEstimator::polishIcpIn(const Hypothesis &h, const CameraIntrinsics &K,
						     const ObjectModel &model, const EstimatorConfig &config, int slot,
						     const IcpConfig &icp)
{
	const size_t pixels = static_cast<size_t>(observedView_.width) * observedView_.height;
	const size_t at = pixels * static_cast<size_t>(std::max(0, slot - 1));
	const PolishBuffers buffers{slot == 0 ? working_.first(pixels) : moreWorking_.subspan(at, pixels),
				    slot == 0 ? cloud_.first(pixels) : moreClouds_.subspan(at, pixels), &rendererOf(slot),
				    renderViewOf(slot)};
	const PolishResult polished = polishInWindow(scoreWindow(K, config), model, h.pose, h.score.depthMin * config.psi1,
						     h.score.depthMax * config.psi2, icp, buffers);
	return fromPolish(polished, h.iteration);
}

// Renders the pose into renderView_ and calls f with every covered pixel
// back-projected (camera frame); false if the render failed.
template <typename F>
bool PoseEstimator::forEachShownPoint(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model,
				      F &&f, int slot)
{
	if (!renderPose(pose, K, model, slot))
		return false;
	const ImageView<float> &view = renderViewOf(slot);
	for (int y = 0; y < view.height; ++y)
		for (int x = 0; x < view.width; ++x) {
			const float z = view.at(x, y);
			if (z > 0)
				f(K.backProject(x, y, z));
		}
	return true;
}

// The centroid (camera frame) of the model surface a pose shows, from its
// render. A half-turn about the model's centre moves that surface when the
// object is not symmetric about it (the can's body beside its handle: by
// 70 mm); moving the turn by the difference puts it back where the
// hypothesis saw it.
std::optional<Eigen::Vector3d> PoseEstimator::shownCentroid(const Pose &pose, const CameraIntrinsics &K,
							    const ObjectModel &model, int slot)
{
	Eigen::Vector3d sum = Eigen::Vector3d::Zero();
	int n = 0;
	if (!forEachShownPoint(
		    pose, K, model,
		    [&](const Eigen::Vector3d &p) {
			    sum += p;
			    ++n;
		    },
		    slot) ||
	    n == 0)
		return std::nullopt;
	return sum / n;
}

// Turns each of the best distinct polished hypotheses by 180 deg about
// every axis, scores the turns and polishes the best few. Each candidate
// runs under the budget check.
PoseEstimator::Hypothesis PoseEstimator::searchHalfTurns(const CameraIntrinsics &K, const ObjectModel &model,
							 const EstimatorConfig &config,
							 std::span<const Hypothesis> polished,
							 const Hypothesis &best, const Eigen::Vector3d &centre)
{
	constexpr int kMaxSources = 4, kMaxKeep = kMaxHalfTurnKeep;
	constexpr double kSameRotation = 20.0 * M_PI / 180.0;
	const HalfTurnConfig &cfg = config.halfTurns;
	const double diameter = model.params().diameter;
	// The best first, then the best-scored polished ones unlike those taken.
	Hypothesis sources[kMaxSources];
	int ns = 0;
	sources[ns++] = best;
	const int want = std::clamp(cfg.candidates, 1, kMaxSources);
	while (ns < want) {
		const Hypothesis *next = nullptr;
		for (const Hypothesis &p : polished) {
			bool distinct = p.valid;
			for (int j = 0; j < ns && distinct; ++j)
				distinct = (p.pose.t - sources[j].pose.t).norm() >= 0.1 * diameter ||
					   rotationAngle(p.pose.R, sources[j].pose.R) >= kSameRotation;
			if (distinct && (!next || p.score.score > next->score.score))
				next = &p;
		}
		if (!next)
			break;
		sources[ns++] = *next;
	}
	const int keepN = std::clamp(cfg.keep, 1, kMaxKeep);
	const ViewTemplates &templates = model.viewTemplates();
	const bool screening = cfg.screen > 0 && !templates.empty();
	Hypothesis found = best;
	for (int c = 0; c < ns; ++c) {
		if (!planner_.stageFits(Stage::kHalfTurns, config.budgetMargin, true))
			break;
		const int64_t start = timer_.last();
		if (screening) {
			screenHalfTurns(K, model, config, sources[c], centre, keepN, c * keepN, found);
			planner_.observeStage(Stage::kHalfTurns, start, true);
			continue;
		}
		const std::optional<Eigen::Vector3d> shown = cfg.align ? shownCentroid(sources[c].pose, K, model)
								      : std::nullopt;
		Hypothesis top[kMaxKeep];
		int nt = 0;
		// The turns of a round of axes are posed and scored side by side on
		// the pool's threads (each with its own render), then ranked in
		// axis order as one thread would.
		constexpr int kRound = 32;
		Hypothesis turns[kRound];
		const auto consider = [&](Hypothesis &h, const Pose &pose, int slot) {
			h.valid = pose.t.z() > 0;
			if (!h.valid)
				return;
			h.pose = pose;
			h.score = score(h.pose, K, model, config, slot);
			h.iteration = sources[c].iteration;
		};
		const int turnCount = halfTurnCount(cfg);
		for (int i0 = 0; i0 < turnCount; i0 += kRound) {
			const int na = std::min(kRound, turnCount - i0);
			workers_.run(na, [&](int k, int slot) {
				const Eigen::Matrix3d turn = halfTurnOf(cfg, i0 + k);
				Pose p = turnedAbout(sources[c].pose, turn, centre);
				if (shown) {
					if (const auto turned = shownCentroid(p, K, model, slot))
						p.t += *shown - *turned;
				}
				consider(turns[k], p, slot);
			});
			for (int k = 0; k < na; ++k)
				if (turns[k].valid)
					insertTop(turns[k], top, nt, keepN);
		}
		polishTurns(std::span<const Hypothesis>(top, static_cast<size_t>(nt)), K, model, config, c * keepN, found);
		planner_.observeStage(Stage::kHalfTurns, start, true);
	}
	return found;
}

// One source's half-turns screened on the view templates: every turn placed
// by its template's centroid and scored sparsely, the `screen` best rendered
// and scored, the keepN best of those polished (reported from rankBase);
// found takes any better one.
void PoseEstimator::screenHalfTurns(const CameraIntrinsics &K, const ObjectModel &model,
				    const EstimatorConfig &config, const Hypothesis &source,
				    const Eigen::Vector3d &centre, int keepN, int rankBase, Hypothesis &found)
{
	constexpr int kMaxScreen = kMaxHalfTurnScreen, kMaxKeep = kMaxHalfTurnKeep;
	const HalfTurnConfig &cfg = config.halfTurns;
	const ViewTemplates &templates = model.viewTemplates();
	const ViewSearchConfig vc = viewScoring(config);
	const BoxAxes axes = boxAxes();
	// Where the source shows its surface, by the same rule as the turns'.
	const int sourceView = nearestView(templates, source.pose);
	if (sourceView < 0)
		return;
	const Eigen::Vector3d shown = source.pose.apply(viewCentroid(templates, sourceView));
	// The best `screen` turns by the sparse score, best first (ties: the
	// earlier axis).
	struct Screened {
		float score;
		Pose pose;
	};
	std::array<Screened, kMaxScreen> screened;
	const int want = std::min(cfg.screen, kMaxScreen);
	int ns = 0;
	for (int i = 0; i < halfTurnCount(cfg); ++i) {
		Pose p = turnedAbout(source.pose, halfTurnOf(cfg, i), centre);
		int v = nearestView(templates, p);
		if (v >= 0 && cfg.align) {
			p.t += shown - p.apply(viewCentroid(templates, v));
			v = nearestView(templates, p);
		}
		if (v < 0)
			continue;
		Eigen::Vector3d t;
		const float s = sparsePoseScore(templates, v, vc, observedView_, K, p, axes, t);
		if (!(s > 0) || (ns == want && s <= screened[static_cast<size_t>(ns - 1)].score))
			continue;
		p.t = t;
		int pos = std::min(ns, want - 1);
		while (pos > 0 && screened[static_cast<size_t>(pos - 1)].score < s) {
			screened[static_cast<size_t>(pos)] = screened[static_cast<size_t>(pos - 1)];
			--pos;
		}
		screened[static_cast<size_t>(pos)] = Screened{s, p};
		ns = std::min(ns + 1, want);
	}
	Hypothesis turns[kMaxScreen];
	workers_.run(ns, [&](int k, int slot) {
		Hypothesis &h = turns[k];
		h.pose = screened[static_cast<size_t>(k)].pose;
		h.valid = h.pose.t.z() > 0;
		if (!h.valid)
			return;
		h.score = score(h.pose, K, model, config, slot);
		h.iteration = source.iteration;
	});
	Hypothesis top[kMaxKeep];
	int nt = 0;
	for (int k = 0; k < ns; ++k)
		if (turns[k].valid)
			insertTop(turns[k], top, nt, keepN);
	polishTurns(std::span<const Hypothesis>(top, static_cast<size_t>(nt)), K, model, config, rankBase, found);
}

// The kept turns' polishes, side by side when there are threads, each
// reported (ranks from rankBase); found takes any better one.
void PoseEstimator::polishTurns(std::span<const Hypothesis> top, const CameraIntrinsics &K, const ObjectModel &model,
				const EstimatorConfig &config, int rankBase, Hypothesis &found)
{
	const int nt = std::min(static_cast<int>(top.size()), kMaxHalfTurnKeep);
	Hypothesis polished[kMaxHalfTurnKeep];
	if (config.icp)
		workers_.run(nt, [&](int j, int slot) {
			polished[j] = polishOn(top[static_cast<size_t>(j)], K, model, config, Stage::kHalfTurns, slot,
					       config.icpConfig);
		});
	for (int j = 0; j < nt; ++j) {
		const Hypothesis &p = polished[j];
		const Hypothesis &r = p.valid ? p : top[static_cast<size_t>(j)];
		report(r.iteration, "half_turn", rankBase + j, r.pose, r.score, 0);
		if (r.score.score > found.score.score)
			found = r;
	}
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

bool PoseEstimator::hypothesisFrame(const Pose &pose, const CameraIntrinsics &K,
				    const ObjectModel &model, UnitCubeFrame &frame)
{
	Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
	Eigen::Vector3f hi = -lo;
	if (!forEachShownPoint(pose, K, model, [&](const Eigen::Vector3d &point) {
		    const Eigen::Vector3f p = point.cast<float>();
		    lo = lo.cwiseMin(p);
		    hi = hi.cwiseMax(p);
	    }))
		return false;
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
	timer_.lap(Stage::kNormalise);
	IbsConfig ibs = params.ibs;
	if (config.ibsMaxPoints > 0)
		ibs.maxPoints = std::min(ibs.maxPoints, config.ibsMaxPoints);
	if (config.ibsCgIterations > 0)
		ibs.cgMaxIterations = std::min(ibs.cgMaxIterations, config.ibsCgIterations);
	auto fit = fitter_.fit(std::span(unit_.data(), cloud.size()),
			       std::span(normals_.data(), cloud.size()), ibs, active_, {}, &workers_);
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
	// Large (near or big) objects: a wider stride keeps the part count near
	// targetParts, so the vote buffer never truncates the last rows' votes
	// and the time per box stays bounded.
	if (config.targetParts > 0) {
		const int wide = static_cast<int>(std::ceil(std::sqrt(static_cast<float>(cloudCount) / config.targetParts)));
		partCfg.stride = std::max(partCfg.stride, wide);
	}
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
	const size_t histSize = kMaxHistogramSlots * static_cast<size_t>(model.forest().dims);
	// Parts [i0, i1) walked in order, their votes appended to out.
	auto walk = [&](int i0, int i1, std::span<float> hist, std::span<CastVote> out) {
		size_t n = 0;
		for (int i = i0; i < i1; ++i) {
			const Part &p = parts_[i];
			std::span<const PartCp> cps(pool_.data() + p.cpOffset, p.cpCount);
			n = castPartVotes(model.forest(), cps, p.centreCamera, params.hocp, params.depthCheckMarginMm,
					  hist, out, n);
		}
		return n;
	};
	// Several threads: each walks a contiguous share of the parts into its
	// share of the vote buffer, and the shares are then joined in part order:
	// the votes of one thread, unless a share filled up (then one thread
	// again, which truncates where one thread always did).
	const int threads = workers_.threads();
	size_t votes = 0;
	bool joined = false;
	if (threads > 1 && partCount >= 2 * threads && hist_.size() >= histSize * static_cast<size_t>(threads)) {
		const size_t share = votes_.size() / static_cast<size_t>(threads);
		std::array<size_t, WorkerPool::kMaxThreads> counts{};
		workers_.run(threads, [&](int c, int thread) {
			counts[static_cast<size_t>(c)] =
				walk(partCount * c / threads, partCount * (c + 1) / threads,
				     hist_.subspan(static_cast<size_t>(thread) * histSize, histSize),
				     votes_.subspan(static_cast<size_t>(c) * share, share));
		});
		joined = std::all_of(counts.begin(), counts.begin() + threads, [&](size_t n) { return n < share; });
		if (joined) {
			votes = counts[0]; // the first share is in place
			for (int c = 1; c < threads; ++c) {
				const auto from = votes_.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(c) * share);
				std::copy(from, from + static_cast<std::ptrdiff_t>(counts[static_cast<size_t>(c)]),
					  votes_.begin() + static_cast<std::ptrdiff_t>(votes));
				votes += counts[static_cast<size_t>(c)];
			}
		}
	}
	if (!joined)
		votes = walk(0, partCount, hist_.first(histSize), votes_);
	timer_.lap(Stage::kForest);
	peaks_.votes = std::max(peaks_.votes, static_cast<int>(votes));
	return static_cast<int>(votes);
}

bool PoseEstimator::renderPose(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model, int slot)
{
	return renderModel(rendererOf(slot), renderViewOf(slot), model, pose, K);
}

ScoreWindow PoseEstimator::scoreWindow(const CameraIntrinsics &K, const EstimatorConfig &config) const
{
	return ScoreWindow{observedView_, K, openSides_, &config.score};
}

void PoseEstimator::setCulling(const ObjectModel &model, const EstimatorConfig &config)
{
	const bool cull = config.cullBackFaces && model.renderMeshClosed();
	renderer_.setCullBackFaces(cull);
	for (DepthRenderer &r : moreRenderers_)
		r.setCullBackFaces(cull);
}

void PoseEstimator::setRenderViews(int w, int h)
{
	const size_t pixels = static_cast<size_t>(w) * h;
	renderView_ = ImageView<float>(render_.data(), w, h, w);
	for (int t = 1; t < workers_.threads(); ++t)
		moreRenderViews_[static_cast<size_t>(t - 1)] =
			ImageView<float>(render_.data() + pixels * static_cast<size_t>(t), w, h, w);
}

void PoseEstimator::scoreAll(std::span<const Pose> poses, std::span<HypothesisScore> scores,
			     const CameraIntrinsics &K, const ObjectModel &model, const EstimatorConfig &config)
{
	workers_.run(static_cast<int>(poses.size()), [&](int i, int thread) {
		const Pose &pose = poses[static_cast<size_t>(i)];
		// Behind the camera: nothing to render (callers skip those).
		scores[static_cast<size_t>(i)] = pose.t.z() > 0 ? score(pose, K, model, config, thread) : HypothesisScore{};
	});
}

HypothesisScore PoseEstimator::score(const Pose &pose, const CameraIntrinsics &K,
				     const ObjectModel &model, const EstimatorConfig &config, int slot)
{
	return scoreInWindow(scoreWindow(K, config), rendererOf(slot), renderViewOf(slot), model, pose);
}

// Scores every vote mode (translation modes x their rotation modes), keeps
// the distinct good ones, and returns this iteration's best.
PoseEstimator::Hypothesis PoseEstimator::scoreModes(int iteration, size_t modeCount,
						    const CameraIntrinsics &K, const ObjectModel &model,
						    const EstimatorConfig &config)
{
	Hypothesis best;
	const float same = static_cast<float>(0.05 * model.params().diameter);
	// Scored side by side on the pool's threads, then kept in mode order.
	constexpr size_t kRound = 32;
	Pose poses[kRound];
	HypothesisScore scores[kRound];
	for (size_t m = 0; m < modeCount; ++m) {
		const size_t k = m % kRound;
		if (k == 0) {
			const size_t n = std::min(kRound, modeCount - m);
			for (size_t j = 0; j < n; ++j) {
				poses[j].R = modes_[m + j].rotation.toRotationMatrix().cast<double>();
				poses[j].t = modes_[m + j].centre.cast<double>();
			}
			scoreAll(std::span<const Pose>(poses, n), std::span<HypothesisScore>(scores, n), K, model, config);
		}
		Hypothesis h;
		h.pose = poses[k];
		if (h.pose.t.z() <= 0)
			continue;
		h.score = scores[k];
		h.iteration = iteration;
		h.valid = true;
		report(iteration, "mode", static_cast<int>(m), h.pose, h.score, modes_[m].rotationDensity);
		keep(h, same, iteration > 0);
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
	if (!valid_)
		return makeError(Errc::kCapacity, "estimator has no memory (arena allocation failed)");
	if (model.renderMesh().vertices.size() > renderer_.capacity())
		return makeError(Errc::kCapacity, "model mesh larger than the estimator's render limit");
	ArenaScope scratch(arena_);
	VirtualCrop crop;
	const CropStatus status = makeVirtualCrop(depth, K, box, observed_, crop);
	if (status == CropStatus::kOutsideImage)
		return makeError(Errc::kInvalidArgument, "box outside the image");
	if (status != CropStatus::kOk)
		return makeError(Errc::kInvalidArgument, "empty box");
	const CameraIntrinsics &vk = crop.intrinsics;
	openSides_ = openSidesOf(box.x, box.y, box.w, box.h, depth.width, depth.height);
	if (!carveBox(arena_, static_cast<size_t>(vk.width) * vk.height))
		return makeError(Errc::kCapacity, "arena too small for the box");
	observedView_ = ImageView<float>(observed_.data(), vk.width, vk.height, vk.width);
	setRenderViews(vk.width, vk.height);
	Pose virt;
	virt.R = crop.rotation.transpose() * pose.R;
	virt.t = crop.rotation.transpose() * pose.t;
	HypothesisScore s = score(virt, vk, model, config);
	releaseBox();
	return s;
}

void PoseEstimator::maskToHypothesis(const HypothesisScore &s, const EstimatorConfig &config)
{
	maskToRange(s.depthMin * config.psi1, s.depthMax * config.psi2);
}

void PoseEstimator::maskToRange(float lo, float hi)
{
	maskToRange(lo, hi, working_);
}

void PoseEstimator::maskToRange(float lo, float hi, std::span<float> out) const
{
	cutToDepthRange(observedView_, lo, hi, out);
}

Expected<WarmUpCost> PoseEstimator::warmUp(const ObjectModel &model, const CameraIntrinsics &K,
					    const EstimatorConfig &config)
{
	if (!valid_)
		return makeError(Errc::kCapacity, "estimator has no memory (arena allocation failed)");
	const double diameter = model.params().diameter;
	if (!(diameter > 0) || K.width <= 0 || K.height <= 0 || !(K.fx > 0) || !(K.fy > 0))
		return makeError(Errc::kInvalidArgument, "warm-up needs a model diameter and the camera's intrinsics");
	// The object across 80 % of the largest window's side, on the optical
	// axis, turned so that no face is seen square on; a wall one diameter
	// behind it gives the box a second depth slab, as a table or shelf does.
	const double side = 0.8 * std::sqrt(static_cast<double>(limits_.maxWindowPixels));
	Pose pose;
	pose.R = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
	pose.t = Eigen::Vector3d(0, 0, std::max(1.5 * diameter, K.fx * diameter / side));
	Image<float> depth(K.width, K.height, 0.0f);
	setCulling(model, config);
	auto rendered = renderer_.render(model.renderMesh(), pose, K, depth.view());
	if (!rendered)
		return rendered.error();
	int x0 = K.width, y0 = K.height, x1 = -1, y1 = -1;
	for (int y = 0; y < K.height; ++y)
		for (int x = 0; x < K.width; ++x) {
			float &d = depth.at(x, y);
			if (d > 0) {
				x0 = std::min(x0, x);
				y0 = std::min(y0, y);
				x1 = std::max(x1, x);
				y1 = std::max(y1, y);
			} else {
				d = static_cast<float>(pose.t.z() + diameter);
			}
		}
	if (x1 < x0)
		return makeError(Errc::kInvalidArgument, "warm-up: the model is not in the camera's view");
	// A detector's box, 10 % larger than the object's.
	const int mx = (x1 - x0) / 20 + 1, my = (y1 - y0) / 20 + 1;
	const PixelBox box{x0 - mx, y0 - my, x1 - x0 + 1 + 2 * mx, y1 - y0 + 1 + 2 * my};

	// The box runs as a frame's only box would: its share is the frame
	// (an unlimited frame: no share profile).
	const ShareSettings share =
		underShare(config, config.frameBudgetMs > 0 ? static_cast<double>(config.frameBudgetMs)
							    : std::numeric_limits<double>::infinity());
	EstimatorConfig c = share.config;
	c.frameBudgetMs = 0;
	EstimateObserver *observer = observer_;
	observer_ = nullptr;
	beginFrame(1, 0);
	const PoseEstimate e = estimate(depth.view(), K, box, model, c);
	endFrame();
	observer_ = observer;

	WarmUpCost cost;
	cost.registrationMs = static_cast<double>(planner_.registrationNs()) * 1e-6;
	cost.boxMs = static_cast<double>(planner_.frame().worstFrameNs()) * 1e-6;
	cost.tight = share.tight;
	cost.parts = e.parts;

	planner_.forgetCounts();
	researches_ = researchWins_ = 0;
	peaks_ = {};
	if (!e.found)
		return makeError(Errc::kNoPose, std::string("warm-up box gave no pose: ") + e.reason);
	return cost;
}

PoseEstimate PoseEstimator::estimate(ImageView<const float> depth, const CameraIntrinsics &K,
				     const PixelBox &box, const ObjectModel &model,
				     const EstimatorConfig &requested)
{
	PoseEstimate out;
	BoxScope scope(*this, requested);
	EstimatorConfig budgeted;
	if (!planner_.unlimited()) {
		const ShareSettings share = underShare(requested, planner_.shareMs());
		budgeted = share.config;
		planner_.counters().tightBoxes += share.tight;
		planner_.counters().shortBoxes += share.shortRounds;
		if (planner_.chooseLeanSearch(static_cast<double>(requested.views.leanSearchBelow)))
			budgeted.views = underLeanBudget(requested.views);
	}
	const EstimatorConfig &config = planner_.unlimited() ? requested : budgeted;
	if (!valid_) {
		out.reason = "estimator has no memory (arena allocation failed)";
		return out;
	}
	if (model.renderMesh().vertices.size() > renderer_.capacity()) {
		out.reason = "model mesh larger than the estimator's render limit";
		return out;
	}
	if (model.forest().dims > limits_.maxHistogramDims) {
		out.reason = "forest histogram longer than the estimator's limit";
		return out;
	}
	setCulling(model, config);
	VirtualCrop cropStorage;
	std::span<float> window = observed_;
	if (config.windowPixels > 0 && static_cast<size_t>(config.windowPixels) < window.size())
		window = window.first(static_cast<size_t>(config.windowPixels));
	const CropStatus cropStatus = makeVirtualCrop(depth, K, box, window, cropStorage);
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
	planner_.setBoxWork(config.budgetScaleByBox ? std::max(1, crop->validPixels) : 1);
	openSides_ = openSidesOf(box.x, box.y, box.w, box.h, depth.width, depth.height);
	const int w = vk.width, h = vk.height;
	peaks_.windowPixels = std::max(peaks_.windowPixels, w * h);
	if (!carveBox(arena_, static_cast<size_t>(w) * h)) {
		out.reason = "arena too small for the box";
		return out;
	}
	observedView_ = ImageView<float>(observed_.data(), w, h, w);
	workingView_ = ImageView<float>(working_.data(), w, h, w);
	setRenderViews(w, h);
	std::copy_n(observed_.data(), static_cast<size_t>(w) * h, working_.data());

	const ModelParams &params = model.params();
	VoteModeConfig modeCfg;
	modeCfg.translationBandwidth = static_cast<float>(config.translationBandwidth * params.diameter);
	modeCfg.rotationBandwidth = config.rotationBandwidthDeg * static_cast<float>(M_PI / 180.0);

	cropRotation_ = crop->rotation;
	keptCount_ = registrationKeptCount_ = 0;
	rivals_.clear();
	modeCfg.rotationModesPerCentre = std::max(1, config.rotationModes);
	modeCfg.maxSeeds = static_cast<int>(seeds_.size());
	const size_t modeSlots = std::min(modes_.size(),
					  static_cast<size_t>(std::max(1, config.maxHypotheses)) *
						  static_cast<size_t>(modeCfg.rotationModesPerCentre));
	// The view search's depth centres use the windows too (at least as many
	// as it asks for), whether or not the registration votes per window.
	const size_t windowsWanted = static_cast<size_t>(std::max(config.depthWindows, config.views.depthCentres));
	windowCount_ = 0;
	if (windowsWanted > 0)
		windowCount_ = findDepthWindows(observedView_,
						static_cast<float>(config.depthWindowWidth * params.diameter),
						windowHist_, windows_.first(std::min(windows_.size(), windowsWanted)));
	const size_t windows = std::min(windowCount_, static_cast<size_t>(std::max(0, config.depthWindows)));
	planAfterPasses(config, requested.iterations, model);
	UnitCubeFrame cube;
	bool haveFrame = false;
	// The forest's own bests, of the registration and of the last
	// refinement: polished even when view proposals outrank them.
	Hypothesis forestBest[2];
	// Refinement iterations vote leaner (the iteration* bounds).
	const EstimatorConfig iterationCfg = forIterations(config);
	for (int k = 0; k <= config.iterations; ++k) {
		if (k > 0 && !planner_.passFits(config.budgetMargin)) {
			out.budgetStopped = true;
			break;
		}
		const StageTotals iterationStart = timer_.totals();
		// The initial registration votes once per depth window (or once on
		// the whole box); refinement once on the masked crop.
		const size_t passes = k == 0 ? std::max<size_t>(1, windows) : 1;
		const EstimatorConfig &voteCfg = k > 0 ? iterationCfg : config;
		modeCfg.maxShiftVotes = voteCfg.maxShiftVotes;
		Hypothesis iterBest;
		for (size_t pass = 0; pass < passes; ++pass) {
			// The first slab always runs (every box gets a pose); a
			// further one only if a pass still fits, with room for the
			// searches and the polish after it (as for an iteration).
			if (pass > 0 && !planner_.passFits(config.budgetMargin)) {
				out.budgetStopped = true;
				break;
			}
			if (k == 0 && windows > 0)
				maskToRange(windows_[pass].nearMm, windows_[pass].farMm);
			int n = buildCloud(workingView_, vk, params);
			if (n < config.minValidPixels)
				continue;
			int partCount = 0;
			int votes = voteOnce(vk, model, voteCfg, n, k > 0 && haveFrame ? &cube : nullptr,
					     partCount);
			out.parts = partCount;
			out.votes = votes;
			if (votes == 0)
				continue;
			if (observer_)
				observer_->onVotes({k, static_cast<int>(pass), cropRotation_,
						    std::span<const CastVote>(votes_.data(), votes)});
			size_t modes = findPoseModes(std::span(votes_.data(), votes), modeCfg,
						     {modeScratch_, seeds_, modeSupport_, modePacked_, &workers_,
						      modeThreadScratch_, modeThreadSupport_},
						     modes_.first(modeSlots));
			timer_.lap(Stage::kModes);
			Hypothesis h = scoreModes(k, modes, vk, model, config);
			timer_.lap(Stage::kScore);
			if (h.valid && (!iterBest.valid || h.score.score > iterBest.score.score))
				iterBest = h;
		}
		// The initial registration's passes are observed together: an
		// over-estimate of one refinement, which keeps the budget safe.
		planner_.observePass(iterationStart, k > 0);
		if (k == 0)
			planner_.endRegistration();
		if (!iterBest.valid)
			break;
		out.iterationsDone = k;
		forestBest[k == 0 ? 0 : 1] = iterBest;
		// Eq. 10: the next iteration sees only this iteration's best
		// hypothesis' depth range.
		if (k < config.iterations) {
			maskToHypothesis(iterBest.score, config);
			haveFrame = config.hypothesisCube && hypothesisFrame(iterBest.pose, vk, model, cube);
			timer_.resume(Stage::kScore); // the hypothesis' render for its cube
		}
	}
	if (keptCount_ == 0) {
		out.reason = "no vote mode (no parts could be described)";
		return out;
	}
	if (viewSearchSize(model.viewTemplates(), config.views) > 0)
		searchViewTemplates(vk, model, config);
	out.budgetStopped = planner_.boxCut();
	Hypothesis best = kept_[0];

	// Polish the best distinct hypotheses: ICP on the crop cut to the
	// hypothesis' own depth range; the best score wins. Each polish must fit
	// the budget.
	const bool polish = config.icp;
	constexpr size_t kMaxPolished = 64; // polishes per box at most
	Hypothesis candidates[kMaxPolished];
	const size_t polishCount = polish ? polishCandidates(config, params.diameter, forestBest, candidates) : 0;
	Hypothesis polished[kMaxPolished];
	size_t polishedCount = 0;
	// Candidates are polished in rounds, one per pool thread (each polish on
	// its own slot), and their results taken in candidate order as one
	// thread would; the budget is checked before each round.
	const size_t round = static_cast<size_t>(workers_.threads());
	Hypothesis icped[kMaxPolished];
	for (size_t c0 = 0; c0 < polishCount; c0 += round) {
		if (!planner_.polishFits(config.budgetMargin)) {
			out.icpSkipped = true;
			break;
		}
		const int64_t icpStart = timer_.last();
		const size_t n = std::min(round, polishCount - c0);
		workers_.run(static_cast<int>(n), [&](int k, int slot) {
			const size_t c = c0 + static_cast<size_t>(k);
			const Hypothesis &cand = candidates[c];
			icped[c] = polishOn(cand, vk, model, config, Stage::kIcp, slot, config.icpConfig);
			polished[c] = icped[c].valid ? icped[c] : cand;
		});
		for (size_t c = c0; c < c0 + n; ++c) {
			if (icped[c].valid) {
				report(icped[c].iteration, "icp", static_cast<int>(c), icped[c].pose, icped[c].score, 0);
				if (icped[c].score.score > best.score.score) {
					best = icped[c];
					out.icpApplied = true;
				}
			}
		}
		polishedCount = c0 + n;
		// The cost model sees the whole round (its clouds are counted
		// under the cloud stage on one thread, under ICP on more).
		planner_.observePolish(icpStart);
	}
	// Refinement's re-search.
	const int research = researchRounds(config, requested.iterations, model);
	if (research > 0 && polishCount > 0) {
		const Hypothesis refined = researchAtBest(vk, model, config, best, research, out.researches);
		if (refined.score.score > best.score.score) {
			best = refined;
			out.icpApplied = true;
		}
		out.budgetStopped = out.budgetStopped || planner_.boxCut();
	}
	// The model's box centre: the half-turns' pivot, and what a symmetric
	// object's rivals are compared by.
	const Eigen::Vector3d centre = boundingBox(model.mesh()).centre().cast<double>();
	if (halfTurnsEnabled(config.halfTurns)) {
		const Hypothesis turned = searchHalfTurns(vk, model, config,
							  std::span<const Hypothesis>(polished, polishedCount), best,
							  centre);
		if (turned.score.score > best.score.score) {
			best = turned;
			out.icpApplied = true;
		}
	}
	out.bestIteration = best.iteration;

	out.found = true;
	out.pose.R = crop->rotation * best.pose.R;
	out.pose.t = crop->rotation * best.pose.t;
	out.score = best.score;
	const double distinctMm = config.confidence.distinctShare * params.diameter;
	const float rival =
		rivals_.bestDistinct(best.pose, model.mesh().vertices, centre, params.symmetric, distinctMm);
	out.margin = std::max(0.0f, best.score.score - rival);
	out.confidence = poseConfidence(best.score.score, out.margin, config.confidence);
	return out;
}

} // namespace ihf
