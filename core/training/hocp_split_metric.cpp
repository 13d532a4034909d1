// SPDX-License-Identifier: MIT
#include "core/training/hocp_split_metric.h"

#include <cmath>
#include <vector>

#include "core/features/hocp.h"

namespace ihf {

void HocpSplitMetric::distances(uint32_t templ, std::span<const uint32_t> samples,
				std::span<float> out) const
{
	const auto &t = set_.samples[templ];
	const auto tHist = set_.histogram(templ);
	// Called from the trainer's worker threads: scratch is per call.
	std::vector<float> h(set_.dims);
	for (size_t i = 0; i < samples.size(); ++i) {
		computeHocpDepthChecked(set_.cps(samples[i]), t.zMin, t.zMax, margin_, hocp_, h);
		out[i] = std::sqrt(hocpDistanceSquared(h, tHist));
	}
}

void HocpSplitMetric::templateOf(uint32_t templ, std::span<float> histogram, float &zMin,
				 float &zMax) const
{
	const auto h = set_.histogram(templ);
	std::copy(h.begin(), h.end(), histogram.begin());
	zMin = set_.samples[templ].zMin;
	zMax = set_.samples[templ].zMax;
}

} // namespace ihf
