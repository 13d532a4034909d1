// SPDX-License-Identifier: MIT
#pragma once

// What `ihf run` and `ihf estimate` say after warming the estimator up on
// an object (PoseEstimator::warmUp) before a budgeted run.

#include <string>

#include "core/common/expected.h"
#include "core/estimation/pose_estimator.h"

namespace ihf::app {

// Empty when all is well. Otherwise one line naming the object: the
// warm-up failed (its first box may overrun: its stages are unmeasured),
// or the warm-up's initial registration took longer than the whole frame
// budget: the registration is never cut short, so boxes as large as the
// warm-up's overrun every frame.
std::string warmUpNote(int objId, const Expected<WarmUpCost> &cost, float frameBudgetMs);

} // namespace ihf::app
