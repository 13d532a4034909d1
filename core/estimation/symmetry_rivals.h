// SPDX-License-Identifier: MIT
#pragma once

// The rival turns of a nearly symmetric object as a proposal source: the best
// pose turned about each of the model's near-symmetries (near_symmetry.h;
// every stepDeg about a continuous axis, the stored turn both ways round about
// a discrete one), a body of revolution also set end over end (a half-turn
// through the trained point about the axis square to its own that points at
// its part: seen from the side, a cup upside down fits the depth as well,
// its handle where it was), and the reported poses that are turns of it
// about a continuous axis (at their own angle, between the steps), each
// compared with the best on the pixels where their renders differ
// (part_evidence.h), not by the whole-silhouette score on which they tie.
// First, when the budget has room, the best is compared the same way with
// its close rivals: the best-scoring hypotheses distinct from it and not
// its turns about a continuous axis (the object upside down and slid along
// its axis covers less of the depth but fits what it covers as well as the
// truth, whose turn it is not); one the depth favours replaces it if,
// polished, it scores nearly as well. A turn the depth favours (its part
// pixels ahead two to one, preferredBy()) replaces the best (then polished,
// when a polish fits the budget, and compared again with its own turns);
// the final comparison says whether the best beat every distinct turn about
// a near-symmetry three to one (decisivelyBy(): decisive) or not (the part
// hidden: ambiguous, with that turn's axis). The end-over-end turn is no
// near-symmetry (training found the body upside down unlike itself from
// above or below) and takes no part in that verdict.
// Not in the paper.

#include <span>

#include <Eigen/Core>

#include "core/estimation/part_evidence.h"
#include "core/estimation/proposal_source.h"
#include "core/estimation/symmetry_turn_config.h"

namespace ihf {

// Turns compared per round at most.
inline constexpr int kMaxSymmetryTurns = 48;
// Turns polished per round at most.
inline constexpr int kMaxSymmetryRivalsPolished = 8;
// Close rivals compared at most.
inline constexpr int kMaxCloseRivals = 8;
// Turns of the best that the estimator itself reported, compared at most.
inline constexpr int kMaxReportedTurns = 4;
static_assert(kMaxCloseRivals <= kMaxSymmetryTurns, "the close rivals are compared in the turns' storage");
static_assert(kMaxReportedTurns <= kMaxCloseRivals, "the reported turns are found as the close rivals are");

// What the last box's comparison found.
struct SymmetryVerdict {
	bool ran = false;       // the best was compared with its turns
	bool turned = false;    // a turn or a close rival replaced the best
	bool decisive = false;  // the best beat every distinct turn on the pixels where they differ
	bool ambiguous = false; // a distinct turn the depth cannot tell from the best
	Eigen::Vector3d axis = Eigen::Vector3d::Zero(); // that turn's axis, model frame
	int compared = 0;       // turns compared in the last round
};

class SymmetryRivalSource : public ProposalSource
{
public:
	bool enabled(const ProposalBox &box) const override;
	// The time a budget keeps for this stage from the stages before it
	// (BudgetPlanner::plan): runs of the comparison and polish rounds of
	// its own; none when it does not run.
	struct KeptTime {
		int runs = 0;
		int polishRounds = 0;
	};
	KeptTime keptTime(const ProposalBox &box) const;
	// The best, or a turn of it that the depth prefers (polished); invalid
	// when the budget stopped it before any comparison.
	Hypothesis propose(ProposalBox &box, const Hypothesis &best, std::span<const Hypothesis> polished) override;
	const SymmetryVerdict &verdict() const { return verdict_; }
	// Forgets the last verdict (a box where the source does not run).
	void clear() { verdict_ = {}; }

private:
	// A pose compared with the best: one of its turns, or a close rival.
	struct Rival {
		Pose pose;
		Eigen::Vector3d axis = Eigen::Vector3d::Zero(); // a turn's, model frame
		bool distinct = false; // its model points lie more than the confidence's distinct share away
		bool reported = false; // a turn the estimator reported (reportedTurnsOf()): it may win, while
				       // the verdict is the steps' and it is not polished again
		bool endOverEnd = false; // the body set end over end (turnsOf()): it may win, while the
					 // verdict is the near-symmetries' turns'
		PartEvidence evidence; // A: the best, B: the rival
		Hypothesis polished;   // the rival polished, when it was
	};
	// best's turns and, about a continuous axis, its end-over-end turn (at
	// most out.size()); returns how many.
	static size_t turnsOf(ProposalBox &box, const Pose &best, std::span<Rival> out);
	// best's turns that the estimator reported itself: the highest-scoring
	// reported poses distinct from it that are its turns about a
	// continuous near-symmetry axis, at their own angle and fitted where
	// turnsOf()'s steps land up to half a step beside the part; at most
	// kMaxReportedTurns and out.size(); returns how many.
	static size_t reportedTurnsOf(ProposalBox &box, const Hypothesis &best, std::span<Rival> out);
	// The highest-scoring reported poses, each a distinct share away from
	// best and from those taken before, that are (turns) or are not its
	// turns about a continuous near-symmetry axis (isTurnOf(); axis: that
	// turn's); at most wanted, kMaxCloseRivals and out.size(); returns how
	// many.
	static size_t reportedRivalsOf(ProposalBox &box, const Pose &best, size_t wanted, bool turns,
				       std::span<Rival> out);
	// best's close rivals: the highest-scoring reported poses, each a
	// distinct share away from it and from those taken before and none a
	// turn of it about a continuous near-symmetry axis, at most
	// SymmetryTurnConfig::closeRivals and out.size(); returns how many.
	static size_t closeRivalsOf(ProposalBox &box, const Hypothesis &best, std::span<Rival> out);
	// Whether pose is, within distinctMm, best turned by any angle about one
	// of the model's continuous near-symmetry axes. Turns about a discrete
	// axis stay close rivals: the polished pose fits better than the turn
	// the comparison makes.
	// axis, when not null: that near-symmetry's axis.
	static bool isTurnOf(const ProposalBox &box, const Pose &best, const Pose &pose, double distinctMm,
			     Eigen::Vector3d *axis = nullptr);
	// best rendered as the window's reference, and each rival compared
	// with it in the window; false when best cannot be rendered.
	// difference: how the rivals differ from best (best's turns by a part,
	// on the box's part window; close rivals over their silhouettes, on
	// the box's own).
	static bool compareWithBest(ProposalBox &box, PartWindow &window, const Pose &best, std::span<Rival> rivals,
				    PoseDifference difference);
	// Each rival rendered and compared with the window's reference.
	static void compareWithReference(ProposalBox &box, PartWindow &window, std::span<Rival *> rivals,
					 PoseDifference difference);
	// The turns the best does not clearly beat, at most
	// SymmetryTurnConfig::polishRivals of them, the one the depth prefers
	// most first, polished and compared again: the turn of a best that is
	// itself a little off lands as far off the truth, its part beside the
	// part the sensor sees, and is heard only once polished. A turn keeps
	// whichever of its two comparisons favours it more.
	static void polishRivals(ProposalBox &box, const Hypothesis &best, std::span<Rival> rivals);
	// Each rival's comparison with the best, for the observer; minPixels:
	// the lead a verdict on them needed at least.
	static void reportComparisons(const ProposalBox &box, const char *kind, int round,
				      std::span<const Rival> rivals, int minPixels);
	// The rival the depth prefers most clearly over the best, or null.
	static const Rival *clearest(std::span<const Rival> rivals, const SymmetryTurnConfig &cfg);
	// The winner as a hypothesis, polished (under `stage`) unless it was.
	static Hypothesis adopt(ProposalBox &box, const Hypothesis &current, const Rival &winner, Stage stage);
	// best compared with its close rivals; the one the depth prefers, polished,
	// if its score stays within SymmetryTurnConfig::closeLoss of best's, else best.
	Hypothesis preferredCloseRival(ProposalBox &box, const Hypothesis &best, std::span<Rival> scratch);

	SymmetryVerdict verdict_;
};

} // namespace ihf
