// SPDX-License-Identifier: MIT
#pragma once

// Conversions between the peers' inputs and PCL clouds, and the ICP both
// PCL peers finish with.

#include <span>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "benchmarks/peers/peer.h"

namespace ihf::peers {

using PclCloud = pcl::PointCloud<pcl::PointNormal>;

PclCloud::Ptr toPcl(const PeerModel &model);
PclCloud::Ptr toPcl(std::span<const CloudPoint> scene);
// Voxel grid with the given leaf (mm); normals averaged and renormalised.
PclCloud::Ptr voxelDown(const PclCloud::Ptr &cloud, float leaf);

struct PclIcpParams {
	float maxCorrespondence = 0.1f; // relative to the diameter
	int iterations = 50;
};

// Point-to-point ICP of the crop onto the model (a view is a part of the
// model, not the other way round), from init (model-to-camera). Returns the
// refined model-to-camera pose and the fitness (mean squared distance of the
// crop points within the correspondence distance, mm^2).
struct PclIcpResult {
	bool converged = false;
	Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();
	double fitness = 0;
};
PclIcpResult pclIcp(const PclCloud::Ptr &model, const PclCloud::Ptr &scene, const Eigen::Matrix4f &init,
		    double diameter, const PclIcpParams &params);

Pose toPose(const Eigen::Matrix4f &m);

} // namespace ihf::peers
