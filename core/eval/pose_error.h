// SPDX-License-Identifier: MIT
#pragma once

// Pose error functions of Hinterstoisser et al. as defined by the BOP
// toolkit (bop_toolkit_lib/pose_error.py), over all model vertices:
//
//   ADD(est, gt) = mean_p || (R_est p + t_est) - (R_gt p + t_gt) ||
//   ADI(est, gt) = mean_p min_q || (R_gt p + t_gt) - (R_est q + t_est) ||
//
// ADI (the "ADD-S" closest-point distance) is used for symmetric objects,
// where a pose equal to the truth up to a symmetry must score zero. Units are
// those of the points (millimetres for BOP models). How errors become scores
// (matching, F1 over z, recall) is set out in evaluation.h.

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/pose.h"

namespace ihf {

enum class PoseMetric {
	kAdd,
	kAdi,
};

const char *poseMetricName(PoseMetric metric); // "ADD" / "ADI"

// Both errors need at least one point (callers check meshes are not empty).
double addError(const Pose &est, const Pose &gt, std::span<const Eigen::Vector3f> points);

// A KD tree over the model points in model coordinates. The nearest
// estimate-transformed point to a GT-transformed point x is found by moving x
// into the estimate's model frame, R_est^T (x - t_est): rigid motions keep
// distances, so one tree per model serves every estimate.
class ClosestPointIndex
{
public:
	explicit ClosestPointIndex(std::vector<Eigen::Vector3f> points);
	~ClosestPointIndex();
	ClosestPointIndex(ClosestPointIndex &&) noexcept;
	ClosestPointIndex &operator=(ClosestPointIndex &&) noexcept;

	const std::vector<Eigen::Vector3f> &points() const;

	// Squared distance from q to the nearest model point.
	double nearestSquared(const Eigen::Vector3d &q) const;

	double adiError(const Pose &est, const Pose &gt) const;

private:
	struct Impl;
	std::unique_ptr<Impl> impl_;
};

// Convenience that builds the tree for one call (tests, one-off use).
double adiError(const Pose &est, const Pose &gt, std::span<const Eigen::Vector3f> points);

// The error function of one object: its model points and which metric its
// symmetry calls for (the KD tree is only built for ADI).
class ObjectPoseError
{
public:
	ObjectPoseError(std::vector<Eigen::Vector3f> points, PoseMetric metric);

	PoseMetric metric() const { return metric_; }
	size_t numPoints() const;
	double operator()(const Pose &est, const Pose &gt) const;

private:
	std::vector<Eigen::Vector3f> points_; // empty when index_ holds them
	std::optional<ClosestPointIndex> index_;
	PoseMetric metric_;
};

} // namespace ihf
