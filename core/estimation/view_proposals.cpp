// SPDX-License-Identifier: MIT
#include "core/estimation/view_proposals.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/estimation/depth_windows.h"

namespace ihf {

namespace {

// Voted translations a box searches at most (ViewSearchConfig::centres).
constexpr int kMaxViewCentres = 4;

} // namespace

ViewSearchConfig viewScoring(const EstimatorConfig &config)
{
	ViewSearchConfig vc = config.views;
	vc.outlierWeight = config.score.outlierWeight;
	vc.occludedWeight = config.score.occludedWeight;
	vc.residualWeight = config.score.residualWeight;
	vc.boxWeight = config.score.boxWeight;
	vc.boxMinFill = config.score.boxMinFill;
	vc.boxMargin = config.score.boxMargin;
	return vc;
}

size_t viewKeep(const EstimatorConfig &config)
{
	return static_cast<size_t>(std::clamp(config.views.keep, 1, kMaxViewKeep));
}

int votedCentres(const EstimatorConfig &config)
{
	return std::clamp(config.views.centres, 1, kMaxViewCentres);
}

size_t searchScored(ProposalBox &box, const Eigen::Vector3d &centre, float anchor, const char *stage,
		    std::span<Hypothesis> out, bool bySize)
{
	ViewSearchConfig vc = viewScoring(box.config); // under a budget: underBudget()'s already
	vc.placeBySize = bySize;
	ViewProposal top[kMaxViewKeep];
	const size_t keepN = std::min(out.size(), static_cast<size_t>(kMaxViewKeep));
	const size_t n = searchViews(box.model.viewTemplates(), vc, box.scorer.window().observed, box.scorer.intrinsics(),
				     centre, std::span<ViewProposal>(top, keepN), box.axes, anchor,
				     &box.workspace.workers(), box.workspace.viewSearch());
	Pose poses[kMaxViewKeep];
	HypothesisScore scores[kMaxViewKeep];
	for (size_t j = 0; j < n; ++j)
		poses[j] = top[j].pose;
	box.scorer.scoreAll(std::span<const Pose>(poses, n), std::span<HypothesisScore>(scores, n));
	for (size_t j = 0; j < n; ++j) {
		Hypothesis &h = out[j];
		h.pose = top[j].pose;
		h.score = scores[j];
		h.origin = HypothesisOrigin::kProposal;
		h.valid = true;
		box.pool.report(h, stage, static_cast<int>(j), top[j].score);
	}
	return n;
}

bool ViewTemplateSource::enabled(const ProposalBox &box) const
{
	return viewSearchSize(box.model.viewTemplates(), box.config.views) > 0;
}

// Centres from the box and the depth alone: on the box's ray (the virtual
// crop's optical axis) at each dense slab's median depth: the
// registration's slabs, then thinner ones of the search's own whose medians
// lie in front of all those (a large object's surface and the wall behind
// it share a thick slab, whose median lies between them; a thin slab behind
// is background, and more centres are more wrong poses that can outscore
// the right one).
size_t ViewTemplateSource::depthAnchors(ProposalBox &box, std::span<float> out)
{
	const ViewSearchConfig &views = box.config.views;
	const ImageView<const float> observed = box.scorer.window().observed;
	SlabBuffers &slabs = box.workspace.slabs();
	size_t na = 0;
	const size_t wanted = static_cast<size_t>(std::max(0, views.depthCentres));
	for (const DepthWindow &slab : slabs.windows.first(std::min(box.slabs, wanted))) {
		const float a = windowMedianDepth(observed, slab, views.anchorShare);
		if (a > 0 && na < out.size())
			out[na++] = a;
	}
	if (!(views.depthCentreWidth > 0 && wanted > 0))
		return na;
	const double diameter = box.model.params().diameter;
	const size_t thin = findDepthWindows(observed, static_cast<float>(views.depthCentreWidth * diameter), slabs.hist,
					     slabs.anchorWindows.first(std::min(slabs.anchorWindows.size(), wanted)));
	// Within half the search's depth alignment of one already searched, a
	// centre adds nothing.
	const float apart = 0.5f * views.maxShiftMm;
	float front = std::numeric_limits<float>::max();
	for (size_t j = 0; j < na; ++j)
		front = std::min(front, out[j]);
	const size_t thick = na;
	for (const DepthWindow &slab : slabs.anchorWindows.first(thin)) {
		const float a = windowMedianDepth(observed, slab, views.anchorShare);
		bool seen = !(a > 0) || a > front - apart;
		for (size_t j = thick; j < na && !seen; ++j)
			seen = std::abs(a - out[j]) < apart;
		if (!seen && na < out.size())
			out[na++] = a;
	}
	return na;
}

// One search at a time, each under the budget: every search but the first
// leaves room for the polish after it (unbudgeted, everything fits). A box
// with no room for even one search eases the search's prediction
// (StageCostModel::refused()): else a cost once measured too high would
// keep the search out of every later box.
Hypothesis ViewTemplateSource::propose(ProposalBox &box, const Hypothesis &, std::span<const Hypothesis>)
{
	const EstimatorConfig &config = box.config;
	BudgetPlanner &planner = box.planner;
	Eigen::Vector3d centres[kMaxViewCentres];
	const size_t nc = box.pool.distinctCentres(0.1 * box.model.params().diameter,
						   std::span<Eigen::Vector3d>(centres, static_cast<size_t>(votedCentres(config))));
	constexpr size_t kMaxAnchors = 8;
	float anchors[kMaxAnchors];
	const size_t na = depthAnchors(box, anchors);
	const size_t keepN = viewKeep(config);
	Hypothesis best;
	int searched = 0;
	// One search, if it fits; its proposals are kept. False when it did not
	// fit (and the rest are off).
	auto searchAt = [&](const Eigen::Vector3d &centre, float anchor, const char *stage, bool bySize = false) {
		const bool first = searched++ == 0;
		if (!planner.searchFits(config.budgetMargin, config.icp && !first ? config.views.budgetPolishRounds : 0)) {
			if (first)
				planner.searchRefused();
			return false;
		}
		const int64_t start = planner.timer().last();
		Hypothesis found[kMaxViewKeep];
		const size_t n = searchScored(box, centre, anchor, stage, std::span<Hypothesis>(found, keepN), bySize);
		for (size_t j = 0; j < n; ++j) {
			box.pool.keep(found[j]);
			takeBetter(best, found[j]);
		}
		planner.observeSearch(start);
		return true;
	};
	auto voted = [&]() {
		for (size_t c = 0; c < nc; ++c)
			if (!searchAt(centres[c], 0.0f, "view"))
				return false;
		return true;
	};
	auto fromDepth = [&]() {
		for (size_t j = 0; j < na; ++j)
			if (!searchAt(Eigen::Vector3d::Zero(), anchors[j], "view_depth"))
				return false;
		return true;
	};
	// Last, in a box trusted on both axes, each rotation placed by the
	// box's size (seeded at the first anchor's depth): an object mostly
	// behind an occluder, which holds the votes and the anchors.
	auto byBoxSize = [&]() {
		return !(config.views.boxSizeSearch && na > 0 && box.axes.x && box.axes.y) ||
		       searchAt(Eigen::Vector3d::Zero(), anchors[0], "view_box", true);
	};
	if (config.views.depthFirst) {
		if (fromDepth() && voted())
			byBoxSize();
	} else if (voted() && fromDepth()) {
		byBoxSize();
	}
	return best;
}

} // namespace ihf
