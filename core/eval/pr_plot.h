// SPDX-License-Identifier: MIT
#pragma once

// Precision-recall curves as a PNG: one panel per z in {0.05, 0.10, 0.15}
// (those present in the report), one coloured curve per object, and a legend
// naming each object, its metric and its mean F1. Drawn with cairo when the
// build found it (libcairo2-dev); otherwise plotting reports kUnsupported.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/common/expected.h"
#include "core/eval/evaluation.h"

namespace ihf {

bool prPlotSupported();

struct RgbImage {
	int width = 0;
	int height = 0;
	std::vector<uint8_t> pixels; // RGB, row-major
};

Expected<RgbImage> renderPrPlot(const EvalReport &report);

// Renders and writes atomically (writePng8).
Status writePrPlot(const std::filesystem::path &file, const EvalReport &report);

} // namespace ihf
