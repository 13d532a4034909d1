// SPDX-License-Identifier: MIT
#pragma once

// The evaluation report as a plain-text table: one row per object (metric,
// diameter, counts, F1 per z, mean F1, recall at 0.1 Phi, median time) and
// a final row of means over objects.

#include <string>

#include "core/eval/evaluation.h"

namespace ihf {

std::string formatEvalTable(const EvalReport &report);

} // namespace ihf
