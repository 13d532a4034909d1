// SPDX-License-Identifier: MIT
#pragma once

// The budget planner of a frame's boxes: asked before every stage that can
// be cut (a refinement pass, a view search, a polish round, the half-turns)
// whether its predicted cost still fits the box's share of the frame, and
// told what each stage cost when it ends. It owns the parts of a budget:
//
//   - the stage timer (one clock read a stage) on the estimator's clock;
//   - the frame budget (a deadline per frame, a share per box, overruns);
//   - the cost models: a running average and spread per stage, per unit of
//     work for the stages whose cost grows with the box's depth pixels,
//     the view search of a lean box kept apart from the budget's own;
//   - the box's plan: what runs after the vote passes (searches and polish
//     rounds), so that a pass is started only with room left for them;
//   - the counters of what the budget cut and refused.
//
// The cold estimator (PoseEstimator) asks it before each of its stages;
// the stream estimator (core/tracking) runs its frames on one, its tracked
// boxes and detections sharing the frame's deadline.

#include <array>
#include <cstdint>

#include "core/runtime/clock.h"
#include "core/runtime/frame_budget.h"
#include "core/runtime/stage_timer.h"

namespace ihf {

// What the budget cut or refused, and the boxes it ran with a leaner
// profile (EstimatorStats).
struct BudgetCounters {
	uint64_t iterations = 0;           // refinement iterations run
	uint64_t budgetStops = 0;          // boxes a stage of which was refused
	uint64_t icpSkipped = 0;           // polish rounds refused
	uint64_t researchesSkipped = 0;    // re-search rounds refused
	uint64_t registrationOverruns = 0; // boxes past their share at the end of the registration
	uint64_t tightBoxes = 0;
	uint64_t shortBoxes = 0;
	uint64_t leanSearchBoxes = 0;
};

class BudgetPlanner
{
public:
	// clock: null for a steady clock; it must outlive the planner.
	explicit BudgetPlanner(const Clock *clock = nullptr);
	BudgetPlanner(const BudgetPlanner &) = delete;
	BudgetPlanner &operator=(const BudgetPlanner &) = delete;

	StageTimer &timer() { return timer_; }
	const StageTimer &timer() const { return timer_; }
	const FrameBudget &frame() const { return budget_; }
	const BudgetCounters &counters() const { return counters_; }
	BudgetCounters &counters() { return counters_; }

	// The boxes until endFrame() share budgetMs (<= 0: unlimited).
	void beginFrame(int boxes, float budgetMs);
	// The frame ends at nowNs (the estimator's: its last stage's lap).
	void endFrame(int64_t nowNs);
	bool inFrame() const { return budget_.inFrame(); }
	bool unlimited() const { return budget_.unlimited(); }
	// The frame's time left, from now (negative: past its deadline).
	double frameLeftMs() const;

	// A box starts now: its share of what is left of the frame.
	void beginBox();
	// The box ends with its last stage's lap; returns that time.
	int64_t endBox();
	int64_t boxStartNs() const { return boxStartNs_; }
	double shareMs() const;
	// Whether the box runs the lean view search: its share holds fewer
	// than `leanSearchBelow` of the budget's searches as measured so far.
	// A lean box does not measure the budget's search, whose cost then
	// eases as a refused stage's does, so that one cost measured too high
	// (the warm-up's large box) does not keep every later box lean.
	bool chooseLeanSearch(double leanSearchBelow);
	// The box's depth pixels: the unit of work of the stages that scale
	// with it (ICP, the half-turns); 1 for fixed costs. Every stage's, until
	// setStageWork() gives one its own.
	void setBoxWork(double work) { work_.fill(work); }
	// The unit of work of `stage` in this box: a nearly symmetric object's
	// turns are compared on a finer window than the box's (part_window.h),
	// and cost by its pixels.
	void setStageWork(Stage stage, double work) { work_[static_cast<size_t>(stage)] = work; }

	// What the box runs after its vote passes: view searches, polish rounds
	// and, last, the stages kept (`keptLast` runs of `kept`, scaled with the
	// box's work, and `keptPolishRounds` polish rounds of their own: a
	// nearly symmetric object's comparison of its turns, the step that
	// places its part, with its turns' polish and the comparison after it).
	void plan(int searches, int polishRounds, Stage kept = Stage::kCount, int keptLast = 0,
		  int keptPolishRounds = 0);
	// Whether a vote pass (a refinement iteration, a further slab) fits
	// with room for the planned searches and polish rounds after it, and
	// for the stages kept last.
	bool passFits(double margin);
	// The stages kept last begin: nothing is kept for them any more (their
	// own polish rounds ask polishFits()).
	void beginKept()
	{
		keptLast_ = 0;
		keptPolishRounds_ = 0;
	}
	// A view search, with polishRounds ICP rounds after it and room for the
	// stages kept last.
	bool searchFits(double margin, int polishRounds);
	// A re-search round, with its polish rounds and room for the stages
	// kept last; refusals counted apart.
	bool researchFits(double margin, int polishRounds);
	// A polish round (ICP and its score), with room for a run of `then`
	// after it (kCount: none) and for the stages kept last; refusals
	// counted apart.
	bool polishFits(double margin, Stage then = Stage::kCount);
	// One run of `stage` (the half-turns), with room for the stages kept
	// last unless it is one of them.
	bool stageFits(Stage stage, double margin, bool scalesWithBox);
	// An optional run of `stage` (scaled with the box) and a polish round
	// after it, with room for the stages kept last; a refusal does not
	// count the box as cut short.
	bool optionalStageFits(Stage stage, double margin);
	// The search's prediction eases (StageCostModel::refused()): wanted
	// but refused, it is not measured again otherwise.
	void searchRefused() { searchCosts().refused(Stage::kViews); }
	// A stage of the current box was refused.
	bool boxCut() const { return boxCut_; }

	// The stages' costs, as they end. `start`: the stage's first lap time.
	void observePass(const StageTotals &start, bool refinement);
	void observeSearch(int64_t start);
	void observePolish(int64_t start);
	void observeStage(Stage stage, int64_t start, bool scalesWithBox);
	// The registration ends with the last lap: its length, and whether the
	// box was past its share already.
	void endRegistration();
	int64_t registrationNs() const { return registrationNs_; }

	// Start-up: the counters, the timer and the frame budget start again;
	// the cost models keep what they measured.
	void forgetCounts();

private:
	int64_t passCost(double margin) const;
	int64_t searchCost(double margin, int polishRounds) const;
	int64_t polishCost(double margin) const;
	int64_t keptCost(double margin) const;
	bool fits(int64_t predictedNs);
	const StageCostModel &searchCosts() const { return leanSearch_ ? leanCosts_ : costs_; }
	StageCostModel &searchCosts() { return leanSearch_ ? leanCosts_ : costs_; }

	SteadyClock steadyClock_;
	StageTimer timer_;
	FrameBudget budget_;
	StageCostModel costs_;
	// The lean searches of short shares, measured apart: costs_ keeps the
	// budget's own search, the unit a share is counted in.
	StageCostModel leanCosts_;
	bool leanSearch_ = false;
	// Each stage's unit of work in the box (setBoxWork(), setStageWork()).
	std::array<double, kStageCount> work_{};
	double workOf(Stage stage) const { return work_[static_cast<size_t>(stage)]; }
	int plannedSearches_ = 0;
	int plannedPolishRounds_ = 0;
	Stage kept_ = Stage::kCount;
	int keptLast_ = 0;
	int keptPolishRounds_ = 0;
	int64_t boxStartNs_ = 0;
	int64_t registrationNs_ = 0;
	bool boxCut_ = false;
	BudgetCounters counters_;
};

} // namespace ihf
