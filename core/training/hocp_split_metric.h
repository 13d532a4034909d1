// SPDX-License-Identifier: MIT
#pragma once

// The split test of the IHF forest (Sect. III-B) over a training set: the
// sample's control points are depth-checked against the template part's
// depth range (plus a margin), re-histogrammed, and compared with the
// template's own histogram by L2 distance.

#include "core/forest/forest_trainer.h"
#include "core/training/training_set.h"

namespace ihf {

class HocpSplitMetric : public SplitMetric
{
public:
	HocpSplitMetric(const TrainingSet &set, const HocpConfig &hocp, float marginMm)
		: set_(set), hocp_(hocp), margin_(marginMm) {}

	int dims() const override { return set_.dims; }
	void distances(uint32_t templ, std::span<const uint32_t> samples,
		       std::span<float> out) const override;
	void templateOf(uint32_t templ, std::span<float> histogram, float &zMin,
			float &zMax) const override;

private:
	const TrainingSet &set_;
	HocpConfig hocp_;
	float margin_;
};

} // namespace ihf
