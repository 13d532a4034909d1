// SPDX-License-Identifier: MIT
#pragma once

// Grows a Hough forest from annotated training parts (paper Sect. III-B).
// The descriptor side (depth check + HoCP distance) is behind SplitMetric so
// the trainer only sees distances; the labels are the parts' votes.

#include <cstdint>
#include <functional>
#include <span>

#include "core/forest/hough_forest.h"

namespace ihf {

class SplitMetric
{
public:
	virtual ~SplitMetric() = default;
	virtual int dims() const = 0;
	// Distance of each sample in `samples` to the template made from sample
	// `templ`: the sample is depth-checked against the template's range.
	virtual void distances(uint32_t templ, std::span<const uint32_t> samples,
			       std::span<float> out) const = 0;
	// The stored form of a template: histogram (dims floats), depth range.
	virtual void templateOf(uint32_t templ, std::span<float> histogram, float &zMin,
				float &zMax) const = 0;
};

enum class SplitObjective {
	kAlternate, // per node, offset or pose entropy at random (LCHF)
	kOffset,
	kPose,
	kSum, // sum of both entropies
};

struct ForestTrainerConfig {
	int trees = 3;
	int maxDepth = 25;
	int maxLeafSamples = 15; // a node with this many samples or fewer is a leaf
	int templatesPerNode = 20; // candidate template parts per split
	float sampleFraction = 0.8f; // bootstrap share of the samples per tree
	SplitObjective objective = SplitObjective::kAlternate;
	float offsetRegulariser = 1.0f; // mm^2 added to offset covariances
	float rotationRegulariser = 1e-4f; // added to quaternion covariances
	uint64_t seed = 1;
	int threads = 2;
};

// progress(done, total): training samples that have reached a leaf.
using TrainProgress = std::function<void(size_t done, size_t total)>;

HoughForest trainForest(const ForestTrainerConfig &config, const SplitMetric &metric,
			std::span<const Vote> labels, const TrainProgress &progress = {});

} // namespace ihf
