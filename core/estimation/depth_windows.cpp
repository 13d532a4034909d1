// SPDX-License-Identifier: MIT
#include "core/estimation/depth_windows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ihf {

size_t findDepthWindows(ImageView<const float> depth, float widthMm, std::span<int> hist,
			std::span<DepthWindow> out)
{
	if (out.empty() || hist.size() < 2 || !(widthMm > 0))
		return 0;
	float lo = std::numeric_limits<float>::max(), hi = 0;
	for (int y = 0; y < depth.height; ++y) {
		const float *r = depth.row(y);
		for (int x = 0; x < depth.width; ++x)
			if (r[x] > 0) {
				lo = std::min(lo, r[x]);
				hi = std::max(hi, r[x]);
			}
	}
	if (!(hi > 0))
		return 0;
	// Bins no finer than 2 mm and enough of them to cover the range.
	const float bin = std::max({2.0f, (hi - lo) / static_cast<float>(hist.size() - 1), widthMm / 64});
	const int bins = std::min(static_cast<int>(hist.size()), static_cast<int>((hi - lo) / bin) + 1);
	std::fill(hist.begin(), hist.begin() + bins, 0);
	for (int y = 0; y < depth.height; ++y) {
		const float *r = depth.row(y);
		for (int x = 0; x < depth.width; ++x)
			if (r[x] > 0)
				hist[std::min(bins - 1, static_cast<int>((r[x] - lo) / bin))]++;
	}
	const int span = std::max(1, static_cast<int>(std::lround(widthMm / bin)));
	size_t found = 0;
	while (found < out.size()) {
		// Densest window; the pixels of chosen windows no longer count, so
		// the next one holds mostly other pixels.
		int bestStart = -1, bestCount = 0, sum = 0;
		for (int b = 0; b < std::min(span, bins); ++b)
			sum += hist[b];
		for (int s = 0; s < bins; ++s) {
			if (s > 0) {
				sum -= hist[s - 1];
				if (s + span - 1 < bins)
					sum += hist[s + span - 1];
			}
			if (sum > bestCount) {
				bestCount = sum;
				bestStart = s;
			}
		}
		if (bestStart < 0)
			break;
		const float nearMm = lo + bestStart * bin;
		out[found++] = DepthWindow{nearMm, nearMm + widthMm, bestCount};
		for (int b = bestStart; b < std::min(bins, bestStart + span); ++b)
			hist[b] = 0;
	}
	return found;
}

namespace {

// Median of the window's pixels inside [x0, x1) x [y0, y1); count gets how
// many there were.
float medianIn(ImageView<const float> depth, const DepthWindow &window, int x0, int y0, int x1, int y1,
	       int &count)
{
	constexpr int kBins = 64;
	const float width = window.farMm - window.nearMm;
	int hist[kBins] = {};
	count = 0;
	for (int y = y0; y < y1; ++y) {
		const float *r = depth.row(y);
		for (int x = x0; x < x1; ++x)
			if (r[x] >= window.nearMm && r[x] < window.farMm) {
				hist[std::min(kBins - 1, static_cast<int>((r[x] - window.nearMm) / width * kBins))]++;
				++count;
			}
	}
	int seen = 0;
	for (int b = 0; b < kBins; ++b) {
		seen += hist[b];
		if (2 * seen >= count && count > 0)
			return window.nearMm + (static_cast<float>(b) + 0.5f) * width / kBins;
	}
	return 0;
}

} // namespace

float windowMedianDepth(ImageView<const float> depth, const DepthWindow &window, float share, int minPixels)
{
	if (!(window.farMm - window.nearMm > 0))
		return 0;
	int count = 0;
	if (share > 0 && share < 1) {
		const int mx = static_cast<int>(std::lround(0.5f * (1 - share) * depth.width));
		const int my = static_cast<int>(std::lround(0.5f * (1 - share) * depth.height));
		const float m = medianIn(depth, window, mx, my, depth.width - mx, depth.height - my, count);
		if (count >= minPixels)
			return m;
	}
	return medianIn(depth, window, 0, 0, depth.width, depth.height, count);
}

} // namespace ihf
