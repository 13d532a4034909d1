// SPDX-License-Identifier: MIT
#include "core/estimation/half_turn_proposals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/estimation/view_proposals.h"
#include "core/pose/half_turns.h"

namespace ihf {

namespace {

constexpr int kMaxSources = 4;

// The best first, then the best-scored polished ones unlike those taken.
size_t turnSources(const Hypothesis &best, std::span<const Hypothesis> polished, int wanted, double diameter,
		   std::span<Hypothesis> out)
{
	constexpr double kSameRotation = 20.0 * M_PI / 180.0;
	size_t n = 0;
	out[n++] = best;
	const size_t want = static_cast<size_t>(std::clamp(wanted, 1, static_cast<int>(out.size())));
	while (n < want) {
		const Hypothesis *next = nullptr;
		for (const Hypothesis &p : polished) {
			bool distinct = p.valid;
			for (size_t j = 0; j < n && distinct; ++j)
				distinct = (p.pose.t - out[j].pose.t).norm() >= 0.1 * diameter ||
					   rotationAngle(p.pose.R, out[j].pose.R) >= kSameRotation;
			if (distinct && (!next || p.score.score > next->score.score))
				next = &p;
		}
		if (!next)
			break;
		out[n++] = *next;
	}
	return n;
}

// A turn as a hypothesis of its source's origin, scored on `slot`; invalid
// behind the camera.
void scoreTurn(ProposalBox &box, const Hypothesis &source, const Pose &pose, int slot, Hypothesis &h)
{
	h.valid = pose.t.z() > 0;
	if (!h.valid)
		return;
	h.pose = pose;
	h.score = box.scorer.score(h.pose, slot);
	h.origin = source.origin;
	h.iteration = source.iteration;
}

} // namespace

bool HalfTurnSource::enabled(const ProposalBox &box) const
{
	return halfTurnsEnabled(box.config.halfTurns);
}

Hypothesis HalfTurnSource::propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis> polished)
{
	const HalfTurnConfig &cfg = box.config.halfTurns;
	Hypothesis sources[kMaxSources];
	const size_t ns = turnSources(best, polished, cfg.candidates, box.model.params().diameter, sources);
	const int keepN = std::clamp(cfg.keep, 1, kMaxHalfTurnKeep);
	const bool screening = cfg.screen > 0 && !box.model.viewTemplates().empty();
	Hypothesis found = best;
	for (size_t c = 0; c < ns; ++c) {
		if (!box.planner.stageFits(Stage::kHalfTurns, box.config.budgetMargin, true))
			break;
		const int64_t start = box.planner.timer().last();
		std::array<Hypothesis, kMaxHalfTurnKeep> storage;
		FixedListBase<Hypothesis> top(std::span<Hypothesis>(storage.data(), static_cast<size_t>(keepN)));
		if (screening)
			screenTurns(box, sources[c], top);
		else
			scoreTurns(box, sources[c], top);
		polishTurns(box, top.items(), static_cast<int>(c) * keepN, found);
		box.planner.observeStage(Stage::kHalfTurns, start, true);
	}
	return found;
}

// The turns of a round of axes are posed and scored side by side on the
// pool's threads (each with its own render), then ranked in axis order as
// one thread would.
void HalfTurnSource::scoreTurns(ProposalBox &box, const Hypothesis &source, FixedListBase<Hypothesis> &top)
{
	const HalfTurnConfig &cfg = box.config.halfTurns;
	const Eigen::Vector3d &centre = box.modelCentre;
	const std::optional<Eigen::Vector3d> shown = cfg.align ? box.scorer.shownCentroid(source.pose) : std::nullopt;
	constexpr int kRound = 32;
	Hypothesis turns[kRound];
	const int turnCount = halfTurnCount(cfg);
	for (int i0 = 0; i0 < turnCount; i0 += kRound) {
		const int na = std::min(kRound, turnCount - i0);
		box.workspace.workers().run(na, [&](int k, int slot) {
			const Eigen::Matrix3d turn = halfTurnOf(cfg, i0 + k);
			Pose p = turnedAbout(source.pose, turn, centre);
			if (shown) {
				if (const auto turned = box.scorer.shownCentroid(p, slot))
					p.t += *shown - *turned;
			}
			scoreTurn(box, source, p, slot, turns[k]);
		});
		for (int k = 0; k < na; ++k)
			if (turns[k].valid)
				insertByScore(top, turns[k]);
	}
}

void HalfTurnSource::screenTurns(ProposalBox &box, const Hypothesis &source, FixedListBase<Hypothesis> &top)
{
	const HalfTurnConfig &cfg = box.config.halfTurns;
	const ViewTemplates &templates = box.model.viewTemplates();
	const ImageView<const float> observed = box.scorer.window().observed;
	const ViewSearchConfig vc = viewScoring(box.config);
	// Where the source shows its surface, by the same rule as the turns'.
	const int sourceView = nearestView(templates, source.pose);
	if (sourceView < 0)
		return;
	const Eigen::Vector3d shown = source.pose.apply(viewCentroid(templates, sourceView));
	// The best `screen` turns by the sparse score, best first (ties: the
	// earlier axis).
	struct Screened {
		float score = 0;
		Pose pose;
	};
	std::array<Screened, kMaxHalfTurnScreen> storage;
	FixedListBase<Screened> screened(
		std::span<Screened>(storage.data(), static_cast<size_t>(std::min(cfg.screen, kMaxHalfTurnScreen))));
	for (int i = 0; i < halfTurnCount(cfg); ++i) {
		Pose p = turnedAbout(source.pose, halfTurnOf(cfg, i), box.modelCentre);
		int v = nearestView(templates, p);
		if (v >= 0 && cfg.align) {
			p.t += shown - p.apply(viewCentroid(templates, v));
			v = nearestView(templates, p);
		}
		if (v < 0)
			continue;
		Eigen::Vector3d t;
		const float s = sparsePoseScore(templates, v, vc, observed, box.scorer.intrinsics(), p, box.axes, t);
		if (!(s > 0))
			continue;
		p.t = t;
		insertRanked(screened, Screened{s, p}, [](const Screened &x) { return x.score; });
	}
	Hypothesis turns[kMaxHalfTurnScreen];
	box.workspace.workers().run(static_cast<int>(screened.size()), [&](int k, int slot) {
		scoreTurn(box, source, screened[static_cast<size_t>(k)].pose, slot, turns[k]);
	});
	for (size_t k = 0; k < screened.size(); ++k)
		if (turns[k].valid)
			insertByScore(top, turns[k]);
}

void HalfTurnSource::polishTurns(ProposalBox &box, std::span<const Hypothesis> top, int rankBase, Hypothesis &found)
{
	Hypothesis polished[kMaxHalfTurnKeep];
	const size_t nt = std::min(top.size(), static_cast<size_t>(kMaxHalfTurnKeep));
	if (box.config.icp)
		box.polisher.polishAll(top.first(nt), std::span<Hypothesis>(polished, nt), Stage::kHalfTurns);
	for (size_t j = 0; j < nt; ++j) {
		const Hypothesis &r = polished[j].valid ? polished[j] : top[j];
		box.pool.report(r, "half_turn", rankBase + static_cast<int>(j));
		takeBetter(found, r);
	}
}

} // namespace ihf
