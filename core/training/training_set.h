// SPDX-License-Identifier: MIT
#pragma once

// The annotated training parts P_i = (c_i, dx_i, theta_i, f_i, D_i) of the
// paper (Eq. 7): rendered positive views of the mesh, each normalised into
// the unit cube at several scale-space factors s_i, fitted with an IBS and
// cut into parts. A part keeps its control points relative to its centre in
// millimetres (the depth check compares physical depths), its HoCP
// histogram, and its vote: the offset from its centre to the object origin
// and the view's rotation.

#include <cstdint>
#include <functional>
#include <vector>

#include "core/common/expected.h"
#include "core/features/part.h"
#include "core/features/part_units.h"
#include "core/forest/hough_forest.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/model/model_params.h"
#include "core/training/view_sampler.h"

namespace ihf {

struct TrainingSetConfig {
	ViewSamplerConfig views;
	std::vector<float> scales{1.0f, 1.4f, 2.0f, 2.8f}; // s_i >= 1
	int partsPerImage = 12; // part centres drawn per (view, scale)
	// Occlusion augmentation (not in the paper, which trains on clean
	// views): this share of the views loses the pixels beyond a random line
	// across the silhouette, between occlusionMin and occlusionMax of them.
	// The unit-cube frame stays that of the whole silhouette, as inference
	// normalises with the whole hypothesis (pose_estimator.h), so an
	// occluded part is described at the scale of the unoccluded object.
	float occludedViews = 0.0f;
	float occlusionMin = 0.1f;
	float occlusionMax = 0.6f;
	int threads = 2;
	uint64_t seed = 1;
};

struct TrainingSample {
	uint32_t cpOffset = 0;
	uint32_t cpCount = 0;
	float zMin = 0; // data depth range relative to the centre, mm
	float zMax = 0;
};

struct TrainingSet {
	int dims = 0;
	std::vector<PartCp> pool;
	std::vector<TrainingSample> samples;
	std::vector<float> histograms; // dims per sample
	std::vector<Vote> labels;
	int views = 0;
	int skippedViews = 0; // views with too few points to describe

	std::span<const PartCp> cps(size_t i) const
	{
		return std::span<const PartCp>(pool).subspan(samples[i].cpOffset, samples[i].cpCount);
	}
	std::span<const float> histogram(size_t i) const
	{
		return std::span<const float>(histograms).subspan(i * dims, dims);
	}
};

// progress(viewsDone, viewsTotal)
using ViewProgress = std::function<void(int done, int total)>;

// The descriptor settings come from params (cloud, ibs, parts, hocp).
Expected<TrainingSet> buildTrainingSet(const Mesh &mesh, const CameraIntrinsics &intrinsics,
				       const ModelParams &params, const TrainingSetConfig &config,
				       const ViewProgress &progress = {});

} // namespace ihf
