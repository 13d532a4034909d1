// SPDX-License-Identifier: MIT
#include "core/estimation/symmetry_rivals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/estimation/pose_distance.h"
#include "core/pose/half_turns.h"

namespace ihf {

namespace {

// Mean distance (mm) between the model points placed by a and by b
// (pose_distance.h).
double meanPoseDistance(std::span<const Eigen::Vector3f> vertices, const Pose &a, const Pose &b)
{
	std::array<Eigen::Vector3d, kPoseDistancePoints> points;
	const int n = sampleModelPoints(vertices, points);
	return meanPointDistance(a, b, std::span<const Eigen::Vector3d>(points.data(), static_cast<size_t>(n)));
}

// Mean distance (mm) the model points move under a turn about (axis, point):
// how far apart the evaluation puts a pose and its turn.
double meanTurnDistance(std::span<const Eigen::Vector3f> vertices, const Eigen::Matrix3d &turn,
			const Eigen::Vector3d &point)
{
	Pose turned;
	turned.R = turn;
	turned.t = point - turn * point;
	return meanPoseDistance(vertices, Pose{}, turned);
}

// How far (mean model-point distance, mm) two poses lie when the confidence
// calls them distinct.
double distinctMmOf(const ProposalBox &box)
{
	return static_cast<double>(box.config.confidence.distinctShare) * box.model.params().diameter;
}

// The direction, square to a continuous near-symmetry's axis, in which the
// mesh reaches farthest from it: the side its part (a cup's handle) is on.
// A half-turn about it sets the body end over end on itself, the part
// where it was.
Eigen::Vector3d partSide(const NearSymmetry &s, std::span<const Eigen::Vector3f> vertices)
{
	const Eigen::Vector3d axis = s.axis.cast<double>().normalized(), point = s.point.cast<double>();
	Eigen::Vector3d side = axis.unitOrthogonal();
	double farthest = 0;
	for (const Eigen::Vector3f &v : vertices) {
		Eigen::Vector3d r = v.cast<double>() - point;
		r -= axis * axis.dot(r);
		if (r.squaredNorm() > farthest) {
			farthest = r.squaredNorm();
			side = r.normalized();
		}
	}
	return side;
}

// Whether the turns the best does not clearly beat are polished and
// compared again (polishRivals()).
bool polishesTurns(const EstimatorConfig &config)
{
	return config.icp && config.symmetryTurns.polishRivals > 0;
}

} // namespace

bool SymmetryRivalSource::enabled(const ProposalBox &box) const
{
	return box.config.symmetryTurns.enabled && !box.model.nearSymmetries().empty();
}

SymmetryRivalSource::KeptTime SymmetryRivalSource::keptTime(const ProposalBox &box) const
{
	if (!enabled(box))
		return {};
	// A body of revolution's turns are many and close together, and the
	// best is told from the nearest of them only once they are polished:
	// their polish and the comparison again are kept too.
	const auto &symmetries = box.model.nearSymmetries();
	const bool revolution = std::any_of(symmetries.begin(), symmetries.end(),
					    [](const NearSymmetry &s) { return s.continuous(); });
	return revolution && polishesTurns(box.config) ? KeptTime{2, 1} : KeptTime{1, 0};
}

size_t SymmetryRivalSource::turnsOf(ProposalBox &box, const Pose &best, std::span<Rival> out)
{
	const SymmetryTurnConfig &cfg = box.config.symmetryTurns;
	const double distinctMm = distinctMmOf(box);
	const std::span<const Eigen::Vector3f> vertices = box.model.mesh().vertices;
	size_t n = 0;
	auto add = [&](const NearSymmetry &s, const Eigen::Vector3d &axis, double deg) -> Rival * {
		if (n >= out.size())
			return nullptr;
		const Eigen::Vector3d point = s.point.cast<double>();
		const Eigen::Matrix3d turn =
			Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
		Rival &t = out[n];
		t = {};
		t.pose = turnedAbout(best, turn, point);
		if (!(t.pose.t.z() > 0))
			return nullptr;
		t.axis = axis;
		t.distinct = meanTurnDistance(vertices, turn, point) > distinctMm;
		return &out[n++];
	};
	for (const NearSymmetry &s : box.model.nearSymmetries()) {
		const Eigen::Vector3d axis = s.axis.cast<double>();
		if (s.continuous()) {
			const int steps = std::max(2, static_cast<int>(std::lround(360.0 / std::max(cfg.stepDeg, 1.0f))));
			for (int k = 1; k < steps; ++k)
				add(s, axis, 360.0 * k / steps);
			if (Rival *t = add(s, partSide(s, vertices), 180.0))
				t->endOverEnd = true;
		} else {
			add(s, axis, s.turnDeg);
			if (std::abs(s.turnDeg - 180.0f) > 1e-3f)
				add(s, axis, -s.turnDeg);
		}
	}
	return n;
}

size_t SymmetryRivalSource::closeRivalsOf(ProposalBox &box, const Hypothesis &best, std::span<Rival> out)
{
	// The best's own turns among the reported poses are left to the turns'
	// comparison, which also says when the depth cannot tell them apart.
	const int wanted = std::clamp(box.config.symmetryTurns.closeRivals, 0, kMaxCloseRivals);
	return reportedRivalsOf(box, best.pose, static_cast<size_t>(wanted), false, out);
}

size_t SymmetryRivalSource::reportedTurnsOf(ProposalBox &box, const Hypothesis &best, std::span<Rival> out)
{
	const size_t n = reportedRivalsOf(box, best.pose, kMaxReportedTurns, true, out);
	for (Rival &t : out.first(n))
		t.reported = true;
	return n;
}

size_t SymmetryRivalSource::reportedRivalsOf(ProposalBox &box, const Pose &best, size_t wanted, bool turns,
					     std::span<Rival> out)
{
	const double distinctMm = distinctMmOf(box);
	// Twice as many asked for as wanted: the reported poses distinct from
	// the best are turns of it and others, in any mix.
	RivalPose reported[2 * kMaxCloseRivals];
	wanted = std::min({wanted, out.size(), static_cast<size_t>(kMaxCloseRivals)});
	const size_t found = box.pool.bestDistinctRivals(best, box.model.mesh().vertices, distinctMm,
							 std::span<RivalPose>(reported, 2 * wanted));
	size_t n = 0;
	for (size_t k = 0; k < found && n < wanted; ++k) {
		Eigen::Vector3d axis = Eigen::Vector3d::Zero();
		if (!(reported[k].pose.t.z() > 0) || isTurnOf(box, best, reported[k].pose, distinctMm, &axis) != turns)
			continue;
		Rival &r = out[n++];
		r = {};
		r.pose = reported[k].pose;
		r.axis = axis;
		r.distinct = true;
	}
	return n;
}

bool SymmetryRivalSource::isTurnOf(const ProposalBox &box, const Pose &best, const Pose &pose, double distinctMm,
				   Eigen::Vector3d *turnAxis)
{
	// pose.R = best.R * Q; the turn about an axis is Q's twist about it.
	const Eigen::Matrix3d q = best.R.transpose() * pose.R;
	for (const NearSymmetry &s : box.model.nearSymmetries()) {
		if (!s.continuous())
			continue;
		const Eigen::Vector3d axis = s.axis.cast<double>().normalized();
		const Eigen::Vector3d u = axis.unitOrthogonal();
		const Eigen::Vector3d turned = q * u;
		const double twist = std::atan2(axis.dot(u.cross(turned)), u.dot(turned));
		const Pose turnedBest =
			turnedAbout(best, Eigen::AngleAxisd(twist, axis).toRotationMatrix(), s.point.cast<double>());
		if (meanPoseDistance(box.model.mesh().vertices, turnedBest, pose) <= distinctMm) {
			if (turnAxis)
				*turnAxis = s.axis.cast<double>();
			return true;
		}
	}
	return false;
}

bool SymmetryRivalSource::compareWithBest(ProposalBox &box, PartWindow &window, const Pose &best,
					  std::span<Rival> rivals, PoseDifference difference)
{
	// The best's render kept; each rival rendered on its thread's slot and
	// compared with it.
	if (!window.render(best, 0))
		return false;
	const ImageView<float> reference = window.reference();
	const ImageView<float> bestRender = window.rendered(0);
	for (int y = 0; y < reference.height; ++y)
		std::copy_n(bestRender.row(y), reference.width, reference.row(y));
	Rival *all[kMaxSymmetryTurns];
	const size_t n = std::min(rivals.size(), std::size(all));
	for (size_t k = 0; k < n; ++k)
		all[k] = &rivals[k];
	compareWithReference(box, window, std::span<Rival *>(all, n), difference);
	return true;
}

void SymmetryRivalSource::compareWithReference(ProposalBox &box, PartWindow &window, std::span<Rival *> rivals,
					       PoseDifference difference)
{
	const ImageView<const float> reference = window.reference();
	const ImageView<const float> observed = window.observed();
	const float tolerance = box.config.score.inlierMm;
	box.workspace.workers().run(static_cast<int>(rivals.size()), [&](int k, int slot) {
		Rival &t = *rivals[static_cast<size_t>(k)];
		t.evidence = {};
		if (window.render(t.pose, slot))
			t.evidence = comparePoseRenders(observed, reference, window.rendered(slot), tolerance, difference);
	});
}

void SymmetryRivalSource::polishRivals(ProposalBox &box, const Hypothesis &best, std::span<Rival> rivals)
{
	const SymmetryTurnConfig &cfg = box.config.symmetryTurns;
	// The polish, then a comparison of the polished turns (on the part
	// window, whose renders cost more than the box's).
	if (!polishesTurns(box.config) || !box.planner.polishFits(box.config.budgetMargin, Stage::kSymmetryTurns))
		return;
	// The turns the best does not clearly beat, the one the depth prefers
	// most first.
	Rival *undecided[kMaxSymmetryTurns];
	size_t nu = 0;
	for (Rival &t : rivals)
		if (!t.reported && !decisivelyBy(t.evidence.forA, t.evidence.forB, t.evidence.informative, cfg))
			undecided[nu++] = &t;
	const auto ahead = [](const Rival *u) { return u->evidence.forB - u->evidence.forA; };
	// Ties keep the turns' order (std::sort, not stable_sort: that one may allocate).
	std::sort(undecided, undecided + nu, [&](const Rival *a, const Rival *b) {
		return ahead(a) != ahead(b) ? ahead(a) > ahead(b) : a < b;
	});
	Rival *picked[kMaxSymmetryRivalsPolished];
	const size_t np = std::min(nu, static_cast<size_t>(std::min(cfg.polishRivals, kMaxSymmetryRivalsPolished)));
	std::copy_n(undecided, np, picked);
	if (np == 0)
		return;
	Hypothesis in[kMaxSymmetryRivalsPolished], out[kMaxSymmetryRivalsPolished];
	for (size_t j = 0; j < np; ++j) {
		in[j].valid = true;
		in[j].pose = picked[j]->pose;
		in[j].score = best.score; // the polish's depth range: the body they share
		in[j].origin = best.origin;
		in[j].iteration = best.iteration;
	}
	box.polisher.polishAll(std::span<const Hypothesis>(in, np), std::span<Hypothesis>(out, np),
			       Stage::kSymmetryTurns);
	// A turn that the polish brought back onto the best keeps its first
	// comparison: where the body alone pulls it back, the part is not what
	// told them apart.
	const double distinctMm = distinctMmOf(box);
	size_t moved = 0;
	Rival raw[kMaxSymmetryRivalsPolished];
	for (size_t j = 0; j < np; ++j) {
		if (!out[j].valid || meanPoseDistance(box.model.mesh().vertices, best.pose, out[j].pose) <= distinctMm)
			continue;
		Rival &t = *picked[j];
		raw[moved] = t;
		t.pose = out[j].pose;
		t.polished = out[j];
		picked[moved++] = &t;
	}
	compareWithReference(box, box.parts, std::span<Rival *>(picked, moved), PoseDifference::kPart);
	// Each turn is judged as the depth likes it best, polished or not: the
	// polish gives a rival its chance, and does not hide one the best does
	// not beat.
	for (size_t j = 0; j < moved; ++j) {
		const PartEvidence &p = picked[j]->evidence, &r = raw[j].evidence;
		if (p.forB - p.forA < r.forB - r.forA)
			*picked[j] = raw[j];
	}
}

void SymmetryRivalSource::reportComparisons(const ProposalBox &box, const char *kind, int round,
					     std::span<const Rival> rivals, int minPixels)
{
	if (!box.pool.observer())
		return;
	for (size_t k = 0; k < rivals.size(); ++k) {
		const Rival &t = rivals[k];
		ComparisonEvent e;
		e.kind = t.endOverEnd ? "end_over_end" : kind;
		e.round = round;
		e.rank = static_cast<int>(k);
		e.rival = t.pose;
		e.axis = t.axis;
		e.distinct = t.distinct;
		e.reported = t.reported;
		e.polished = t.polished.valid;
		e.score = t.polished.valid ? t.polished.score.score : -1;
		e.evidence = t.evidence;
		e.minPixels = minPixels;
		box.pool.reportComparison(e);
	}
}

const SymmetryRivalSource::Rival *SymmetryRivalSource::clearest(std::span<const Rival> rivals,
								const SymmetryTurnConfig &cfg)
{
	const Rival *winner = nullptr;
	for (const Rival &t : rivals) {
		const PartEvidence &e = t.evidence;
		if (preferredBy(e.forB, e.forA, e.informative, cfg) &&
		    (!winner || e.forB - e.forA > winner->evidence.forB - winner->evidence.forA))
			winner = &t;
	}
	return winner;
}

Hypothesis SymmetryRivalSource::preferredCloseRival(ProposalBox &box, const Hypothesis &best,
						    std::span<Rival> scratch)
{
	const int64_t start = box.planner.timer().last();
	size_t n = closeRivalsOf(box, best, scratch);
	// They differ over their silhouettes: the box's own window serves.
	PartWindow window(box.workspace, box.model, box.scorer.window(), 0);
	if (!compareWithBest(box, window, best.pose, scratch.first(n), PoseDifference::kSilhouette))
		n = 0;
	box.planner.observeStage(Stage::kCloseRivals, start, true);
	reportComparisons(box, "close_rival", 0, scratch.first(n), box.config.symmetryTurns.minPixels);
	const Rival *winner = clearest(scratch.first(n), box.config.symmetryTurns);
	if (!winner)
		return best;
	// Taken only if, polished, its whole-silhouette score stays within
	// closeLoss of the best's: on a real sensor's noise a pose turned well
	// off can explain more of the pixels where the two differ and still fit
	// the object worse.
	const Hypothesis h = adopt(box, best, *winner, Stage::kCloseRivals);
	if (h.score.score < best.score.score - box.config.symmetryTurns.closeLoss) {
		box.pool.report(h, "close_rival_refused", 0);
		return best;
	}
	box.pool.report(h, "close_rival", 0);
	verdict_.turned = true;
	return h;
}

Hypothesis SymmetryRivalSource::adopt(ProposalBox &box, const Hypothesis &current, const Rival &winner, Stage stage)
{
	if (winner.polished.valid)
		return winner.polished;
	Hypothesis h;
	h.valid = true;
	h.pose = winner.pose;
	h.score = box.scorer.score(h.pose);
	h.origin = current.origin;
	h.iteration = current.iteration;
	// Inside a budget the polish must fit: the turn itself is exact about
	// the axis, and the time is the final polish's.
	if (!box.config.icp || !box.planner.polishFits(box.config.budgetMargin))
		return h;
	Hypothesis polished[1];
	box.polisher.polishAll(std::span<const Hypothesis>(&h, 1), polished, stage);
	return polished[0].valid ? polished[0] : h;
}

Hypothesis SymmetryRivalSource::propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis>)
{
	verdict_ = {};
	const SymmetryTurnConfig &cfg = box.config.symmetryTurns;
	Rival rivals[kMaxSymmetryTurns];
	Hypothesis current = best;
	if (cfg.closeRivals > 0 && box.planner.optionalStageFits(Stage::kCloseRivals, box.config.budgetMargin))
		current = preferredCloseRival(box, best, rivals);
	box.planner.beginKept();
	for (int round = 0; round < std::max(cfg.rounds, 1); ++round) {
		if (!box.planner.stageFits(Stage::kSymmetryTurns, box.config.budgetMargin, true))
			break;
		const int64_t start = box.planner.timer().last();
		size_t n = turnsOf(box, current.pose, std::span<Rival>(rivals, kMaxSymmetryTurns));
		n += reportedTurnsOf(box, current, std::span<Rival>(rivals + n, kMaxSymmetryTurns - n));
		if (!compareWithBest(box, box.parts, current.pose, std::span<Rival>(rivals, n), PoseDifference::kPart))
			n = 0;
		box.planner.observeStage(Stage::kSymmetryTurns, start, true);
		// The rivals' polish is a polish round of its own (polishFits(),
		// with room for comparing the polished turns again): the stage's
		// cost, and the time a budget keeps for it, is the comparison's
		// alone.
		polishRivals(box, current, std::span<Rival>(rivals, n));
		box.planner.timer().resume(Stage::kSymmetryTurns);
		verdict_.ran = true;
		verdict_.compared = static_cast<int>(n);
		verdict_.ambiguous = false;
		verdict_.decisive = false;
		// The turn the depth prefers most clearly, if any.
		const Rival *winner = clearest(std::span<const Rival>(rivals, n), cfg);
		// Certain only on a lead the box's own window would count too: a
		// budget's poses are polished less, and on the finer part window a
		// lead of a few pixels is as often their misalignment as the part.
		SymmetryTurnConfig certain = cfg;
		certain.minPixels = static_cast<int>(std::lround(cfg.minPixels * box.parts.fineness()));
		int distinctTurns = 0, beaten = 0;
		for (size_t k = 0; k < n; ++k) {
			const Rival &t = rivals[k];
			if (!t.distinct || t.reported || t.endOverEnd)
				continue;
			++distinctTurns;
			if (decisivelyBy(t.evidence.forA, t.evidence.forB, t.evidence.informative, certain)) {
				++beaten;
			} else if (!verdict_.ambiguous) {
				verdict_.ambiguous = true;
				verdict_.axis = t.axis;
			}
		}
		reportComparisons(box, "turn", round, std::span<const Rival>(rivals, n), certain.minPixels);
		if (!winner || round + 1 == std::max(cfg.rounds, 1)) {
			verdict_.decisive = distinctTurns > 0 && beaten == distinctTurns;
			if (winner)
				verdict_.ambiguous = true; // still a turn ahead when the rounds ran out
			break;
		}
		// The preferred turn replaces the best, polished (unless it was
		// already); then its own turns are compared with it.
		current = adopt(box, current, *winner, Stage::kSymmetryTurns);
		box.pool.report(current, "symmetry_turn", round);
		verdict_.turned = true;
	}
	return current;
}

} // namespace ihf
