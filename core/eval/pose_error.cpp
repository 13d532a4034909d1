// SPDX-License-Identifier: MIT
#include "core/eval/pose_error.h"

#include <cassert>
#include <cmath>
#include <limits>

#include <nanoflann.hpp>

namespace ihf {

const char *poseMetricName(PoseMetric metric)
{
	return metric == PoseMetric::kAdi ? "ADI" : "ADD";
}

double addError(const Pose &est, const Pose &gt, std::span<const Eigen::Vector3f> points)
{
	assert(!points.empty());
	// (R_e p + t_e) - (R_g p + t_g) = (R_e - R_g) p + (t_e - t_g)
	const Eigen::Matrix3d dR = est.R - gt.R;
	const Eigen::Vector3d dt = est.t - gt.t;
	double sum = 0;
	for (const Eigen::Vector3f &p : points)
		sum += (dR * p.cast<double>() + dt).norm();
	return sum / static_cast<double>(points.size());
}

struct ClosestPointIndex::Impl {
	// nanoflann's dataset adaptor over a vector of points. Nested, not in an
	// anonymous namespace: a field of such a type draws GCC's
	// -Wsubobject-linkage once a unity build includes this file.
	struct PointCloudAdaptor {
		const std::vector<Eigen::Vector3f> *points;

		size_t kdtree_get_point_count() const { return points->size(); }
		float kdtree_get_pt(size_t idx, size_t dim) const { return (*points)[idx][dim]; }
		template<class Bbox>
		bool kdtree_get_bbox(Bbox &) const { return false; }
	};
	using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointCloudAdaptor>,
							   PointCloudAdaptor, 3, uint32_t>;

	explicit Impl(std::vector<Eigen::Vector3f> pts)
		: points(std::move(pts)), adaptor{&points},
		  tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10))
	{
	}

	std::vector<Eigen::Vector3f> points;
	PointCloudAdaptor adaptor;
	KdTree tree; // builds its index in the constructor
};

ClosestPointIndex::ClosestPointIndex(std::vector<Eigen::Vector3f> points)
	: impl_(std::make_unique<Impl>(std::move(points)))
{
}

ClosestPointIndex::~ClosestPointIndex() = default;
ClosestPointIndex::ClosestPointIndex(ClosestPointIndex &&) noexcept = default;
ClosestPointIndex &ClosestPointIndex::operator=(ClosestPointIndex &&) noexcept = default;

const std::vector<Eigen::Vector3f> &ClosestPointIndex::points() const
{
	return impl_->points;
}

double ClosestPointIndex::nearestSquared(const Eigen::Vector3d &q) const
{
	const std::vector<Eigen::Vector3f> &points = impl_->points;
	const Eigen::Vector3f qf = q.cast<float>();
	uint32_t index = 0;
	float distSq = 0;
	if (impl_->tree.knnSearch(qf.data(), 1, &index, &distSq) == 0)
		return std::numeric_limits<double>::infinity();
	// The tree works in float; the distance to the point it found is
	// recomputed in double so exact matches give exactly zero.
	return (points[index].cast<double>() - q).squaredNorm();
}

double ClosestPointIndex::adiError(const Pose &est, const Pose &gt) const
{
	const std::vector<Eigen::Vector3f> &points = impl_->points;
	assert(!points.empty());
	// GT point x = R_g p + t_g seen in the estimate's model frame:
	// R_e^T (x - t_e) = (R_e^T R_g) p + R_e^T (t_g - t_e).
	const Eigen::Matrix3d R = est.R.transpose() * gt.R;
	const Eigen::Vector3d t = est.R.transpose() * (gt.t - est.t);
	double sum = 0;
	for (const Eigen::Vector3f &p : points)
		sum += std::sqrt(nearestSquared(R * p.cast<double>() + t));
	return sum / static_cast<double>(points.size());
}

double adiError(const Pose &est, const Pose &gt, std::span<const Eigen::Vector3f> points)
{
	ClosestPointIndex index(std::vector<Eigen::Vector3f>(points.begin(), points.end()));
	return index.adiError(est, gt);
}

ObjectPoseError::ObjectPoseError(std::vector<Eigen::Vector3f> points, PoseMetric metric)
	: metric_(metric)
{
	if (metric == PoseMetric::kAdi)
		index_.emplace(std::move(points));
	else
		points_ = std::move(points);
}

size_t ObjectPoseError::numPoints() const
{
	return index_ ? index_->points().size() : points_.size();
}

double ObjectPoseError::operator()(const Pose &est, const Pose &gt) const
{
	return index_ ? index_->adiError(est, gt) : addError(est, gt, points_);
}

} // namespace ihf
