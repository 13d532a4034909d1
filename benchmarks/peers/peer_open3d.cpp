// SPDX-License-Identifier: MIT
#include "benchmarks/peers/peer_open3d.h"

#include <exception>
#include <functional>

#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/CorrespondenceChecker.h>
#include <open3d/pipelines/registration/Feature.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>
#include <open3d/utility/Random.h>

namespace ihf::peers {

namespace reg = open3d::pipelines::registration;
using open3d::geometry::PointCloud;

struct Open3dPeer::Prepared {
	std::shared_ptr<PointCloud> coarse;
	std::shared_ptr<reg::Feature> features;
	std::shared_ptr<PointCloud> fine;
	double diameter = 0;
};

namespace {

std::shared_ptr<PointCloud> downsample(const PointCloud &cloud, double voxel)
{
	auto d = cloud.VoxelDownSample(voxel);
	d->NormalizeNormals();
	return d;
}

} // namespace

Open3dPeer::Open3dPeer(const Open3dParams &params) : params_(params)
{
	open3d::utility::random::Seed(params.seed);
}

Open3dPeer::~Open3dPeer() = default;

Status Open3dPeer::prepare(const PeerModel &model)
{
	auto p = std::make_unique<Prepared>();
	p->diameter = model.diameter;
	PointCloud full;
	for (size_t i = 0; i < model.points.size(); ++i) {
		full.points_.push_back(model.points[i].cast<double>());
		full.normals_.push_back(model.normals[i].cast<double>());
	}
	try {
		p->coarse = downsample(full, params_.voxel * model.diameter);
		p->fine = downsample(full, params_.icpVoxel * model.diameter);
		p->features = reg::ComputeFPFHFeature(
			*p->coarse, open3d::geometry::KDTreeSearchParamHybrid(params_.featureRadius * model.diameter,
									      params_.featureMaxNn));
	} catch (const std::exception &e) {
		return makeError(Errc::kInvalidArgument, std::string("Open3D: ") + e.what());
	}
	models_[model.objId] = std::move(p);
	return {};
}

PeerEstimate Open3dPeer::estimate(int objId, std::span<const CloudPoint> scene)
{
	PeerEstimate out;
	auto it = models_.find(objId);
	if (it == models_.end()) {
		out.reason = "no model";
		return out;
	}
	const Prepared &m = *it->second;
	const double d = m.diameter;
	try {
		PointCloud full;
		full.points_.reserve(scene.size());
		full.normals_.reserve(scene.size());
		for (const CloudPoint &q : scene) {
			full.points_.push_back(q.p.cast<double>());
			full.normals_.push_back(q.n.cast<double>());
		}
		auto crop = downsample(full, params_.voxel * d);
		if (crop->points_.size() < 10) {
			out.reason = "fewer than 10 points in the crop";
			return out;
		}
		auto cropFeatures = reg::ComputeFPFHFeature(
			*crop, open3d::geometry::KDTreeSearchParamHybrid(params_.featureRadius * d, params_.featureMaxNn));
		reg::CorrespondenceCheckerBasedOnEdgeLength edge(params_.edgeLength);
		reg::CorrespondenceCheckerBasedOnDistance dist(params_.ransacDistance * d);
		std::vector<std::reference_wrapper<const reg::CorrespondenceChecker>> checkers{edge, dist};
		reg::RegistrationResult coarse = reg::RegistrationRANSACBasedOnFeatureMatching(
			*m.coarse, *crop, *m.features, *cropFeatures, false, params_.ransacDistance * d,
			reg::TransformationEstimationPointToPoint(false), 3, checkers,
			reg::RANSACConvergenceCriteria(params_.ransacIterations, params_.ransacConfidence));
		if (coarse.correspondence_set_.empty()) {
			out.reason = "RANSAC found no pose";
			return out;
		}
		// Point-to-plane ICP with the crop as source (it is a part of the
		// model), so the result is inverted.
		auto fineCrop = downsample(full, params_.icpVoxel * d);
		reg::RegistrationResult fine = reg::RegistrationICP(
			*fineCrop, *m.fine, params_.icpDistance * d, coarse.transformation_.inverse(),
			reg::TransformationEstimationPointToPlane(),
			reg::ICPConvergenceCriteria(1e-6, 1e-6, params_.icpIterations));
		Eigen::Matrix4d T = coarse.transformation_;
		if (fine.fitness_ > 0)
			T = fine.transformation_.inverse();
		out.pose.R = T.block<3, 3>(0, 0);
		out.pose.t = T.block<3, 1>(0, 3);
		out.score = coarse.fitness_;
		out.found = true;
	} catch (const std::exception &e) {
		out.reason = std::string("Open3D: ") + e.what();
	}
	return out;
}

} // namespace ihf::peers
