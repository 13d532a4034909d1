// SPDX-License-Identifier: MIT
#include "core/estimation/budget_planner.h"

namespace ihf {

BudgetPlanner::BudgetPlanner(const Clock *clock) : timer_(clock ? *clock : steadyClock_)
{
	work_.fill(1.0);
}

void BudgetPlanner::beginFrame(int boxes, float budgetMs)
{
	budget_.beginFrame(timer_.clock().nowNs(), static_cast<int64_t>(budgetMs * 1e6), boxes);
}

void BudgetPlanner::endFrame(int64_t nowNs)
{
	budget_.endFrame(nowNs);
}

double BudgetPlanner::frameLeftMs() const
{
	return static_cast<double>(budget_.frameDeadline() - timer_.now()) * 1e-6;
}

void BudgetPlanner::beginBox()
{
	boxStartNs_ = timer_.start();
	registrationNs_ = 0; // until this box's registration ends
	budget_.beginBox(boxStartNs_);
	boxCut_ = false;
	leanSearch_ = false;
	work_.fill(1.0);
}

int64_t BudgetPlanner::endBox()
{
	const int64_t now = timer_.last();
	budget_.endBox(now);
	return now;
}

double BudgetPlanner::shareMs() const
{
	return static_cast<double>(budget_.boxDeadline() - boxStartNs_) * 1e-6;
}

bool BudgetPlanner::chooseLeanSearch(double leanSearchBelow)
{
	// In the budget's searches as this machine has run them (none yet, as
	// in the warm-up: the budget's search).
	const double searchMs = static_cast<double>(costs_.average(Stage::kViews)) * 1e-6;
	leanSearch_ = shareMs() < leanSearchBelow * searchMs;
	if (leanSearch_)
		costs_.refused(Stage::kViews);
	counters_.leanSearchBoxes += leanSearch_;
	return leanSearch_;
}

void BudgetPlanner::plan(int searches, int polishRounds, Stage kept, int keptLast, int keptPolishRounds)
{
	plannedSearches_ = searches;
	plannedPolishRounds_ = polishRounds;
	kept_ = kept;
	keptLast_ = kept == Stage::kCount ? 0 : keptLast;
	keptPolishRounds_ = kept == Stage::kCount ? 0 : keptPolishRounds;
}

// One vote pass, predicted from the refinement iterations and the initial
// registrations seen so far (a registration of several slabs is observed as
// one: an over-estimate, which keeps the budget safe).
int64_t BudgetPlanner::passCost(double margin) const
{
	return costs_.predict({Stage::kCloud, Stage::kNormalise, Stage::kIbsFit, Stage::kParts, Stage::kHocp,
			       Stage::kForest, Stage::kModes, Stage::kScore},
			      margin);
}

int64_t BudgetPlanner::polishCost(double margin) const
{
	return costs_.bound(Stage::kIcp, margin, workOf(Stage::kIcp));
}

int64_t BudgetPlanner::keptCost(double margin) const
{
	if (kept_ == Stage::kCount)
		return 0;
	return (keptLast_ > 0 ? keptLast_ * costs_.bound(kept_, margin, workOf(kept_)) : 0) +
	       (keptPolishRounds_ > 0 ? keptPolishRounds_ * polishCost(margin) : 0);
}

int64_t BudgetPlanner::searchCost(double margin, int polishRounds) const
{
	return searchCosts().bound(Stage::kViews, margin) + polishRounds * polishCost(margin) + keptCost(margin);
}

bool BudgetPlanner::passFits(double margin)
{
	// Room is kept for what runs after the last pass: the view searches,
	// the polish and the re-search. A pass taking their time costs more
	// than it gains: a box cut to one polish round after all its passes
	// places small objects far less often than one with its searches.
	return fits(passCost(margin) + plannedSearches_ * searchCosts().bound(Stage::kViews, margin) +
		    plannedPolishRounds_ * polishCost(margin) + keptCost(margin));
}

bool BudgetPlanner::searchFits(double margin, int polishRounds)
{
	return fits(searchCost(margin, polishRounds));
}

bool BudgetPlanner::researchFits(double margin, int polishRounds)
{
	if (fits(searchCost(margin, polishRounds)))
		return true;
	++counters_.researchesSkipped;
	return false;
}

bool BudgetPlanner::polishFits(double margin, Stage then)
{
	const int64_t after = then == Stage::kCount ? 0 : costs_.bound(then, margin, workOf(then));
	// A refused polish round does not count the box as cut short.
	if (budget_.fits(timer_.now(), polishCost(margin) + after + keptCost(margin)))
		return true;
	++counters_.icpSkipped;
	return false;
}

bool BudgetPlanner::optionalStageFits(Stage stage, double margin)
{
	if (budget_.fits(timer_.now(), costs_.bound(stage, margin, workOf(stage)) + polishCost(margin) + keptCost(margin)))
		return true;
	costs_.refused(stage);
	return false;
}

bool BudgetPlanner::stageFits(Stage stage, double margin, bool scalesWithBox)
{
	// The stage kept last keeps no room for itself.
	const int64_t kept = stage == kept_ ? 0 : keptCost(margin);
	return fits(costs_.bound(stage, margin, scalesWithBox ? workOf(stage) : 1.0) + kept);
}

// Whether predictedNs more still fits the frame and the box; a box is
// counted as cut short once, whichever stage the budget refused.
bool BudgetPlanner::fits(int64_t predictedNs)
{
	if (budget_.fits(timer_.now(), predictedNs))
		return true;
	if (!boxCut_)
		++counters_.budgetStops;
	boxCut_ = true;
	return false;
}

void BudgetPlanner::observePass(const StageTotals &start, bool refinement)
{
	costs_.observe(start, timer_.totals());
	counters_.iterations += refinement;
}

void BudgetPlanner::observeSearch(int64_t start)
{
	searchCosts().observe(Stage::kViews, timer_.lap(Stage::kViews) - start);
}

void BudgetPlanner::observePolish(int64_t start)
{
	// The whole round (its clouds are counted under the cloud stage on
	// one thread, under ICP on more).
	costs_.observe(Stage::kIcp, timer_.lap(Stage::kIcp) - start, workOf(Stage::kIcp));
}

void BudgetPlanner::observeStage(Stage stage, int64_t start, bool scalesWithBox)
{
	costs_.observe(stage, timer_.lap(stage) - start, scalesWithBox ? workOf(stage) : 1.0);
}

void BudgetPlanner::endRegistration()
{
	// The last lap's time: a new clock read would move a step clock.
	registrationNs_ = timer_.last() - boxStartNs_;
	if (!budget_.unlimited() && timer_.last() > budget_.boxDeadline())
		++counters_.registrationOverruns;
}

void BudgetPlanner::forgetCounts()
{
	timer_.reset();
	budget_ = FrameBudget{};
	counters_ = {};
}

} // namespace ihf
