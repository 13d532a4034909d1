// SPDX-License-Identifier: MIT
#include "core/runtime/stage_timer.h"

#include <algorithm>
#include <cmath>

namespace ihf {

const char *stageName(Stage stage)
{
	switch (stage) {
	case Stage::kCrop: return "crop";
	case Stage::kCloud: return "cloud";
	case Stage::kNormalise: return "normalise";
	case Stage::kIbsFit: return "ibs_fit";
	case Stage::kParts: return "parts";
	case Stage::kHocp: return "hocp";
	case Stage::kForest: return "forest";
	case Stage::kModes: return "vote_modes";
	case Stage::kScore: return "render_score";
	case Stage::kViews: return "views";
	case Stage::kIcp: return "icp";
	case Stage::kHalfTurns: return "half_turns";
	case Stage::kCloseRivals: return "close_rivals";
	case Stage::kSymmetryTurns: return "symmetry_turns";
	case Stage::kCount: break;
	}
	return "unknown";
}

StageTotals StageTimer::totals() const
{
	StageTotals t{};
	for (int i = 0; i < kStageCount; ++i)
		t[i] = counters_[i].totalNs;
	return t;
}

void StageCostModel::observe(Stage stage, int64_t ns, double work)
{
	const int i = static_cast<int>(stage);
	const double x = static_cast<double>(ns) / std::max(work, 1e-9);
	if (!seen_[i]) {
		average_[i] = x;
		deviation_[i] = 0.25 * x;
		seen_[i] = true;
	} else {
		// A stall (the thread preempted, a page fault) is one observation
		// far outside the spread. Taken as is, it prices the stage out of
		// every later frame, and a stage that no longer runs is never
		// observed again to correct it (syn200 at 33 ms: one 52 ms view
		// search, a quarter fewer searches for the rest of the run, mean F1
		// 0.77 against 0.85 without the stall). So the step is clipped; a lasting change still
		// comes through within a few observations, as each clipped step
		// widens the spread. Clipped nearer (4 deviations), the bunny's
		// large boxes overran more often: its costs are heavy-tailed.
		const double limit = kClipDeviations * std::max(deviation_[i], kSpreadFloor * average_[i]);
		const double error = std::clamp(x - average_[i], -limit, limit);
		average_[i] += alpha_ * error;
		deviation_[i] += alpha_ * (std::abs(error) - deviation_[i]);
	}
}

void StageCostModel::observe(const StageTotals &before, const StageTotals &after)
{
	for (int i = 0; i < kStageCount; ++i)
		if (after[i] != before[i])
			observe(static_cast<Stage>(i), after[i] - before[i]);
}

int64_t StageCostModel::average(Stage stage) const
{
	return static_cast<int64_t>(std::ceil(average_[static_cast<int>(stage)]));
}

int64_t StageCostModel::bound(Stage stage, double margin, double work) const
{
	const int i = static_cast<int>(stage);
	return static_cast<int64_t>(std::ceil((average_[i] + std::max(0.0, margin) * deviation_[i]) * work));
}

void StageCostModel::refused(Stage stage)
{
	const int i = static_cast<int>(stage);
	average_[i] *= kRefusedEase;
	deviation_[i] *= kRefusedEase;
}

int64_t StageCostModel::predict(std::initializer_list<Stage> stages, double margin) const
{
	int64_t sum = 0;
	for (Stage s : stages)
		sum += bound(s, margin);
	return sum;
}

} // namespace ihf
