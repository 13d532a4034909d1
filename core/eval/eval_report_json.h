// SPDX-License-Identifier: MIT
#pragma once

// The evaluation report as JSON: z values, per object (metric, diameter,
// counts, F1 per z, mean F1, recall at 0.1 Phi, median time or null, and the
// precision-recall curve at z = 0.10), and the means over objects.

#include <filesystem>
#include <string>

#include "core/common/expected.h"
#include "core/eval/evaluation.h"

namespace ihf {

std::string evalReportJson(const EvalReport &report);

// Written to a temporary file beside `file` and renamed into place.
Status writeEvalReportJson(const std::filesystem::path &file, const EvalReport &report);

// Index of z = 0.10 (the curve kept in the JSON and drawn first), or -1.
int curveZIndex(const EvalReport &report, double z = 0.10);

} // namespace ihf
