// SPDX-License-Identifier: MIT
#pragma once

// Per-stage time counters of the inference path (PX4-style perf counters:
// fixed at start-up, begin/end around each stage). StageTimer works as a lap
// timer: lap(stage) charges the time since the previous lap to `stage`, so a
// sequence of stages costs one clock read per stage.
//
// StageCostModel keeps a running average (exponential, per stage) of what a
// stage cost per refinement iteration, which is how the frame budget
// predicts the next iteration before starting it.

#include <array>
#include <cstdint>
#include <initializer_list>

#include "core/runtime/clock.h"

namespace ihf {

enum class Stage : uint8_t {
	kCrop,      // virtual on-axis crop of the box
	kCloud,     // Eq. 10 mask + back-projection with normals
	kNormalise, // unit-cube frame and normalised points (Eq. 1-2)
	kIbsFit,    // 3L implicit B-spline fit
	kParts,     // part extraction
	kHocp,      // parts to mm + HoCP keys
	kForest,    // forest walk, incl. the per-node depth-checked histograms
	kModes,     // vote mode finding
	kScore,     // rendering and scoring the hypotheses
	kViews,     // view-template rotation search at the best translations (optional)
	kIcp,       // final ICP polish and its score
	kHalfTurns, // half-turns of the polished best, scored and polished (optional)
	kCloseRivals,   // a nearly symmetric object's best compared with its close rivals where they differ
	kSymmetryTurns, // turns about a nearly symmetric object's axes, compared where they differ
	kCount,
};

constexpr int kStageCount = static_cast<int>(Stage::kCount);

const char *stageName(Stage stage);

struct StageCounter {
	uint64_t calls = 0;
	int64_t totalNs = 0;
	int64_t maxNs = 0;
};

using StageTotals = std::array<int64_t, kStageCount>;

class StageTimer
{
public:
	explicit StageTimer(const Clock &clock) : clock_(&clock) {}

	void setClock(const Clock &clock) { clock_ = &clock; }
	const Clock &clock() const { return *clock_; }

	// Starts lap timing; returns the time read.
	int64_t start()
	{
		last_ = clock_->nowNs();
		return last_;
	}

	// Charges the time since the last lap (or start) to stage; returns now.
	int64_t lap(Stage stage)
	{
		const int64_t now = clock_->nowNs();
		const int64_t dt = now - last_;
		StageCounter &c = counters_[static_cast<int>(stage)];
		int64_t &resumed = resumed_[static_cast<int>(stage)];
		c.calls++;
		c.totalNs += dt;
		// The call's length includes what resume() charged to it.
		if (dt + resumed > c.maxNs)
			c.maxNs = dt + resumed;
		resumed = 0;
		last_ = now;
		return now;
	}

	// Charges the time since the last lap to `stage` without counting a
	// call: a stage resumed within another's call (the ICP inside the
	// half-turns), so that calls still count whole stage runs.
	int64_t resume(Stage stage)
	{
		const int64_t now = clock_->nowNs();
		counters_[static_cast<int>(stage)].totalNs += now - last_;
		resumed_[static_cast<int>(stage)] += now - last_;
		last_ = now;
		return now;
	}

	// Reads the clock without charging anything (the time still goes to
	// the next lap).
	int64_t now() const { return clock_->nowNs(); }

	// Time of the last lap (no new read).
	int64_t last() const { return last_; }

	const std::array<StageCounter, kStageCount> &counters() const { return counters_; }
	StageTotals totals() const;
	void reset()
	{
		counters_ = {};
		resumed_ = {};
	}

private:
	const Clock *clock_;
	int64_t last_ = 0;
	std::array<StageCounter, kStageCount> counters_{};
	std::array<int64_t, kStageCount> resumed_{}; // charged by resume() since the stage's last lap
};

class StageCostModel
{
public:
	// alpha: weight of the newest observation in the running average.
	explicit StageCostModel(double alpha = 0.3) : alpha_(alpha) {}

	// One iteration's cost per stage: the difference of two totals()
	// snapshots. Stages that did not run in it are left alone.
	void observe(const StageTotals &before, const StageTotals &after);
	// One run of a stage whose cost grows with `work` (e.g. the box's depth
	// pixels; 1: a fixed cost): the model keeps the cost per unit of work.
	// A cost far outside the running spread counts as a few deviations.
	void observe(Stage stage, int64_t ns, double work = 1.0);

	// Predicted cost of running the given stages once more (0 for a stage
	// never observed): each stage's bound().
	int64_t predict(std::initializer_list<Stage> stages, double margin = 0) const;
	int64_t average(Stage stage) const; // per unit of work
	// The running average plus `margin` running mean absolute deviations
	// (margin 0: the average): a cost the stage exceeds less often, for
	// budgets that must not overrun. One observation says nothing of the
	// spread, so it starts at a quarter of the first cost.
	int64_t bound(Stage stage, double margin, double work = 1.0) const;
	// The budget refused a run of the stage that was wanted (not merely cut
	// short): its prediction eases by kRefusedEase. A stage that no longer
	// runs is never observed again, so one cost measured too high (the
	// warm-up box's cold first search) would keep it out of every later
	// frame; eased, it is tried again and measured. A stage that truly does
	// not fit is then refused again until it has eased as far once more.
	void refused(Stage stage);

private:
	// 0.97: a stage predicted 1.3x the room left runs again after 9
	// refusals; one predicted at twice the room after 23.
	static constexpr double kRefusedEase = 0.97;
	// An observation moves the model by at most this many deviations from
	// the average (the deviation taken as at least kSpreadFloor of it).
	static constexpr double kClipDeviations = 8.0;
	static constexpr double kSpreadFloor = 0.1;
	double alpha_;
	std::array<double, kStageCount> average_{};
	std::array<double, kStageCount> deviation_{};
	std::array<bool, kStageCount> seen_{};
};

} // namespace ihf
