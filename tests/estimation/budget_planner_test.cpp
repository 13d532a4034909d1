// SPDX-License-Identifier: MIT
// The budget planner (core/estimation/budget_planner.h) on a manual clock:
// a stage never measured is predicted free; a measured one fits only while
// its cost bound is left in the box's share; a vote pass is refused when it
// would leave no room for the planned searches and polish rounds, and a
// pass or a search none for the stage kept last (nor for that stage's own
// polish rounds when it has some); an optional stage fits
// with a polish and the stage kept last after it; a polish round and
// another stage keep that room too, until the kept stage begins; polish
// and re-search refusals are counted apart from the boxes cut short; a lean
// box's search is measured apart from the budget's own; a stage given a
// unit of work of its own is predicted by it, also when a polish round
// asks room for it; forgetting the counts keeps the cost models.

#include <initializer_list>
#include <utility>

#include <gtest/gtest.h>

#include "core/estimation/budget_planner.h"

namespace ihf {
namespace {

constexpr int64_t kMs = 1000000;

class ManualClock final : public Clock
{
public:
	int64_t nowNs() const override { return t; }
	int64_t t = 0;
};

// One run of `stage` lasting ms, observed by the planner.
void run(BudgetPlanner &p, ManualClock &clock, Stage stage, int64_t ms)
{
	const int64_t start = p.timer().last();
	clock.t += ms * kMs;
	if (stage == Stage::kViews)
		p.observeSearch(start);
	else if (stage == Stage::kIcp)
		p.observePolish(start);
	else
		p.observeStage(stage, start, false);
}

// An unlimited frame that measures one box: a 2 ms vote pass, then each
// (stage, ms) run in turn.
void measureABox(BudgetPlanner &p, ManualClock &clock, std::initializer_list<std::pair<Stage, int64_t>> runs)
{
	p.beginFrame(1, 0.0f); // unlimited: measure
	p.beginBox();
	const StageTotals before = p.timer().totals();
	clock.t += 2 * kMs;
	p.timer().lap(Stage::kForest);
	p.observePass(before, true);
	for (const auto &[stage, ms] : runs)
		run(p, clock, stage, ms);
	p.endFrame(p.endBox());
}

TEST(BudgetPlanner, AStageNeverMeasuredIsPredictedFree)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	p.beginFrame(1, 10.0f);
	p.beginBox();
	clock.t += 9 * kMs;
	EXPECT_TRUE(p.stageFits(Stage::kHalfTurns, 0, false));
	EXPECT_TRUE(p.polishFits(0));
	EXPECT_FALSE(p.boxCut());
}

TEST(BudgetPlanner, AMeasuredStageFitsOnlyWhileItsCostIsLeft)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	p.beginFrame(1, 20.0f);
	p.beginBox();
	run(p, clock, Stage::kHalfTurns, 4);
	EXPECT_TRUE(p.stageFits(Stage::kHalfTurns, 0, false)); // 4 ms used, 16 left
	clock.t += 13 * kMs;                                    // 3 ms left
	EXPECT_FALSE(p.stageFits(Stage::kHalfTurns, 0, false));
	EXPECT_TRUE(p.boxCut());
	EXPECT_FALSE(p.stageFits(Stage::kHalfTurns, 0, false));
	EXPECT_EQ(p.counters().budgetStops, 1u); // a box is cut short once
	p.endFrame(p.endBox());
	EXPECT_EQ(p.frame().frames(), 1u);
	EXPECT_EQ(p.frame().frameOverruns(), 0u);
}

TEST(BudgetPlanner, APassKeepsRoomForThePlannedSearchesAndPolish)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	measureABox(p, clock, {{Stage::kViews, 3}, {Stage::kIcp, 1}});
	EXPECT_EQ(p.counters().iterations, 1u);

	// 12 ms: a pass (2) fits alone, and with two searches (6) and two
	// polish rounds (2) after it, but not with three searches more.
	p.beginFrame(1, 12.0f);
	p.beginBox();
	p.plan(2, 2);
	EXPECT_TRUE(p.passFits(0));
	p.plan(5, 2);
	EXPECT_FALSE(p.passFits(0));
	EXPECT_EQ(p.counters().budgetStops, 1u);
}

TEST(BudgetPlanner, PassesAndSearchesKeepRoomForTheStageKeptLast)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	measureABox(p, clock, {{Stage::kViews, 3}, {Stage::kSymmetryTurns, 4}});

	// 8 ms: a pass (2) and a search (3) fit alone, but not with the
	// comparison (4) kept after them.
	p.beginFrame(1, 8.0f);
	p.beginBox();
	p.plan(1, 0);
	EXPECT_TRUE(p.passFits(0));
	EXPECT_TRUE(p.searchFits(0, 0));
	p.plan(1, 0, Stage::kSymmetryTurns, 1);
	EXPECT_FALSE(p.passFits(0));
	clock.t += 1 * kMs; // 7 ms left: the search and the comparison fit
	EXPECT_TRUE(p.searchFits(0, 0));
	clock.t += 1 * kMs; // 6 ms left: the search would leave no room for it
	EXPECT_FALSE(p.searchFits(0, 0));
	EXPECT_FALSE(p.researchFits(0, 0));
	EXPECT_TRUE(p.stageFits(Stage::kSymmetryTurns, 0, false)); // the kept stage itself still fits
}

TEST(BudgetPlanner, TheStageKeptLastKeepsRoomForItsOwnPolishToo)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	measureABox(p, clock, {{Stage::kViews, 3}, {Stage::kIcp, 2}, {Stage::kSymmetryTurns, 2}});

	// 12 ms, 8 left after a pass: a search (3) fits with one comparison (2)
	// kept after it, not with two comparisons and the turns' polish
	// between them (2 + 2 + 2).
	p.beginFrame(1, 12.0f);
	p.beginBox();
	clock.t += 4 * kMs;
	p.plan(1, 0, Stage::kSymmetryTurns, 1);
	EXPECT_TRUE(p.searchFits(0, 0));
	p.plan(1, 0, Stage::kSymmetryTurns, 2, 1);
	EXPECT_FALSE(p.searchFits(0, 0));
	EXPECT_FALSE(p.passFits(0));
	// 9 left: now it fits.
	p.beginFrame(1, 13.0f);
	p.beginBox();
	clock.t += 4 * kMs;
	p.plan(1, 0, Stage::kSymmetryTurns, 2, 1);
	EXPECT_TRUE(p.searchFits(0, 0));
	// Once the comparison begins, its polish needs only its own time and
	// a comparison after it.
	clock.t += 5 * kMs; // 4 left
	EXPECT_FALSE(p.polishFits(0, Stage::kSymmetryTurns));
	p.beginKept();
	EXPECT_TRUE(p.polishFits(0, Stage::kSymmetryTurns));
}

TEST(BudgetPlanner, AnOptionalStageFitsWithAPolishAndTheStageKeptLast)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	measureABox(p, clock, {{Stage::kCloseRivals, 1}, {Stage::kIcp, 2}, {Stage::kSymmetryTurns, 3}});

	// 10 ms: with 7 left the close rivals (1), a polish (2) and the kept
	// comparison (3) fit; with 5 left they do not, and the box is not
	// counted as cut short: the kept stage still runs.
	p.beginFrame(1, 10.0f);
	p.beginBox();
	p.plan(0, 0, Stage::kSymmetryTurns, 1);
	clock.t += 3 * kMs;
	EXPECT_TRUE(p.optionalStageFits(Stage::kCloseRivals, 0));
	clock.t += 2 * kMs;
	EXPECT_FALSE(p.optionalStageFits(Stage::kCloseRivals, 0));
	EXPECT_FALSE(p.boxCut());
	EXPECT_EQ(p.counters().budgetStops, 0u);
	EXPECT_TRUE(p.stageFits(Stage::kSymmetryTurns, 0, false));
}

TEST(BudgetPlanner, PolishAndOtherStagesKeepRoomForTheStageKeptLastUntilItBegins)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	measureABox(p, clock, {{Stage::kHalfTurns, 2}, {Stage::kIcp, 2}, {Stage::kSymmetryTurns, 3}});

	// 10 ms, 6 left: a polish round (2) or the half-turns (2) fit alone
	// and with the comparison (3) after them; 4 left: they fit alone but
	// not with it, while the comparison itself does.
	p.beginFrame(1, 10.0f);
	p.beginBox();
	p.plan(0, 0, Stage::kSymmetryTurns, 1);
	clock.t += 4 * kMs;
	EXPECT_TRUE(p.polishFits(0));
	EXPECT_TRUE(p.stageFits(Stage::kHalfTurns, 0, false));
	clock.t += 2 * kMs;
	EXPECT_FALSE(p.polishFits(0));
	EXPECT_EQ(p.counters().icpSkipped, 1u);
	EXPECT_FALSE(p.stageFits(Stage::kHalfTurns, 0, false));
	EXPECT_TRUE(p.stageFits(Stage::kSymmetryTurns, 0, false));
	// Once the comparison begins, its own polish rounds need only their time.
	p.beginKept();
	EXPECT_TRUE(p.polishFits(0));
}

TEST(BudgetPlanner, AStageWithWorkOfItsOwnIsPredictedByIt)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	// Measured in a box of 100 depth pixels: a polish round 2 ms, the
	// comparison of the turns 3 ms (its window as fine as the box's).
	p.beginFrame(1, 0.0f);
	p.beginBox();
	p.setBoxWork(100);
	int64_t start = p.timer().last();
	clock.t += 2 * kMs;
	p.observePolish(start);
	start = p.timer().last();
	clock.t += 3 * kMs;
	p.observeStage(Stage::kSymmetryTurns, start, true);
	p.endFrame(p.endBox());

	// A box as large, its turns compared on a window of 300 pixels: the
	// comparison is predicted at 9 ms, the polish still at 2.
	p.beginFrame(1, 10.0f);
	p.beginBox();
	p.setBoxWork(100);
	p.setStageWork(Stage::kSymmetryTurns, 300);
	p.plan(0, 0, Stage::kSymmetryTurns, 1);
	clock.t += 1 * kMs; // 9 ms left
	EXPECT_TRUE(p.stageFits(Stage::kSymmetryTurns, 0, true));
	EXPECT_FALSE(p.polishFits(0)); // 2 + 9 do not fit
	clock.t += 1 * kMs; // 8 ms left
	EXPECT_FALSE(p.stageFits(Stage::kSymmetryTurns, 0, true));
	p.beginKept();
	EXPECT_TRUE(p.polishFits(0));
	// A polish of the turns with a comparison of them after it: 2 + 9.
	EXPECT_FALSE(p.polishFits(0, Stage::kSymmetryTurns));
	p.endFrame(p.endBox());

	// The next box starts with every stage at its own box's work again.
	p.beginFrame(1, 10.0f);
	p.beginBox();
	p.setBoxWork(100);
	clock.t += 2 * kMs; // 8 ms left
	EXPECT_TRUE(p.stageFits(Stage::kSymmetryTurns, 0, true));
}

TEST(BudgetPlanner, PolishAndResearchRefusalsAreCountedApart)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	p.beginFrame(1, 0.0f);
	p.beginBox();
	run(p, clock, Stage::kViews, 5);
	run(p, clock, Stage::kIcp, 5);
	p.endFrame(p.endBox());

	p.beginFrame(1, 4.0f);
	p.beginBox();
	EXPECT_FALSE(p.polishFits(0));
	EXPECT_EQ(p.counters().icpSkipped, 1u);
	EXPECT_FALSE(p.boxCut()); // a refused polish does not cut the box
	EXPECT_FALSE(p.researchFits(0, 1));
	EXPECT_EQ(p.counters().researchesSkipped, 1u);
	EXPECT_TRUE(p.boxCut());
}

TEST(BudgetPlanner, ALeanBoxMeasuresItsSearchApart)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	p.beginFrame(1, 0.0f);
	p.beginBox();
	run(p, clock, Stage::kViews, 10);
	p.endFrame(p.endBox());

	// A 15 ms share holds fewer than two 10 ms searches: lean.
	p.beginFrame(1, 15.0f);
	p.beginBox();
	EXPECT_TRUE(p.chooseLeanSearch(2.0));
	EXPECT_EQ(p.counters().leanSearchBoxes, 1u);
	run(p, clock, Stage::kViews, 1); // the lean search
	EXPECT_TRUE(p.searchFits(0, 0)); // 1 ms, lean: fits in 14
	p.endFrame(p.endBox());

	// The budget's search kept its own cost (eased once by the lean box).
	p.beginFrame(1, 9.0f);
	p.beginBox();
	EXPECT_FALSE(p.chooseLeanSearch(0.5)); // 9 ms holds half of ~9.7 ms
	EXPECT_FALSE(p.searchFits(0, 0));
}

TEST(BudgetPlanner, ForgettingTheCountsKeepsTheCosts)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	p.beginFrame(1, 0.0f);
	p.beginBox();
	run(p, clock, Stage::kIcp, 6);
	p.endRegistration();
	EXPECT_EQ(p.registrationNs(), 6 * kMs);
	p.endFrame(p.endBox());
	p.forgetCounts();
	EXPECT_EQ(p.frame().frames(), 0u);
	EXPECT_EQ(p.timer().counters()[static_cast<int>(Stage::kIcp)].calls, 0u);
	p.beginFrame(1, 5.0f);
	p.beginBox();
	EXPECT_FALSE(p.polishFits(0)); // still predicted at 6 ms
}

TEST(BudgetPlanner, TheRegistrationPastItsShareIsCounted)
{
	ManualClock clock;
	BudgetPlanner p(&clock);
	p.beginFrame(2, 10.0f);
	p.beginBox();
	EXPECT_DOUBLE_EQ(p.shareMs(), 5.0);
	clock.t += 7 * kMs;
	p.timer().lap(Stage::kForest);
	p.endRegistration();
	EXPECT_EQ(p.counters().registrationOverruns, 1u);
	EXPECT_NEAR(p.frameLeftMs(), 3.0, 1e-9);
}

} // namespace
} // namespace ihf
