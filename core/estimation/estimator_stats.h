// SPDX-License-Identifier: MIT
#pragma once

// What the inference path reports about itself: time per stage, the frame
// budget's bookkeeping, the arena and how much of each configured limit the
// largest box really used (so limits and arena can be sized from
// measurement).

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/runtime/stage_timer.h"

namespace ihf {

struct EstimatorPeaks {
	int windowPixels = 0;        // virtual crop window (EstimatorLimits::maxWindowPixels)
	int cloudPoints = 0;
	int activeControlPoints = 0; // maxActive
	int parts = 0;               // maxParts
	int poolControlPoints = 0;   // maxParts * maxPartControlPoints
	int votes = 0;               // maxVotes
};

struct EstimatorStats {
	std::array<StageCounter, kStageCount> stages{};

	uint64_t frames = 0;
	uint64_t boxes = 0;
	uint64_t iterations = 0;          // refinement iterations run (k >= 1)
	uint64_t budgetStops = 0;         // boxes whose refinement the budget cut short
	uint64_t icpSkipped = 0;          // ICP polishes skipped for want of time
	uint64_t researches = 0;          // refinement's re-search rounds run
	                                  // (EstimatorConfig::researchRounds)
	uint64_t researchWins = 0;        // of those, rounds that found a better pose
	uint64_t researchesSkipped = 0;   // rounds the budget left out
	uint64_t frameOverruns = 0;       // frames that ended past their budget
	uint64_t boxOverruns = 0;         // boxes that ended past their share
	uint64_t registrationOverruns = 0; // of those, past it at the end of the initial
	                                   // registration already (never cut short: the
	                                   // frame is shorter than it)
	uint64_t tightBoxes = 0;          // boxes run with the tight budget's leaner
	                                  // registration (EstimatorConfig::budgetTightMs)
	uint64_t shortBoxes = 0;          // boxes polished with the short share's ICP
	                                  // rounds (EstimatorConfig::budgetShortMs)
	uint64_t leanSearchBoxes = 0;     // boxes whose share held too few view searches
	                                  // (ViewSearchConfig::leanSearchBelow)
	int64_t worstFrameNs = 0;

	size_t arenaCapacity = 0;
	size_t arenaPersistent = 0;       // buffers sized at start-up
	size_t arenaHighWater = 0;        // persistent + the largest box's scratch
	EstimatorPeaks peaks;
};

} // namespace ihf
