// SPDX-License-Identifier: MIT
#include "benchmarks/peers/pcl_cloud.h"

#include <pcl/filters/voxel_grid.h>
#include <pcl/registration/icp.h>

namespace ihf::peers {

PclCloud::Ptr toPcl(const PeerModel &model)
{
	PclCloud::Ptr c(new PclCloud);
	c->resize(model.points.size());
	for (size_t i = 0; i < model.points.size(); ++i) {
		pcl::PointNormal &q = (*c)[i];
		q.getVector3fMap() = model.points[i];
		q.getNormalVector3fMap() = model.normals[i];
	}
	return c;
}

PclCloud::Ptr toPcl(std::span<const CloudPoint> scene)
{
	PclCloud::Ptr c(new PclCloud);
	c->resize(scene.size());
	for (size_t i = 0; i < scene.size(); ++i) {
		pcl::PointNormal &q = (*c)[i];
		q.getVector3fMap() = scene[i].p;
		q.getNormalVector3fMap() = scene[i].n;
	}
	return c;
}

PclCloud::Ptr voxelDown(const PclCloud::Ptr &cloud, float leaf)
{
	PclCloud::Ptr out(new PclCloud);
	pcl::VoxelGrid<pcl::PointNormal> grid;
	grid.setLeafSize(leaf, leaf, leaf);
	grid.setInputCloud(cloud);
	grid.filter(*out);
	for (pcl::PointNormal &q : *out) {
		float n = q.getNormalVector3fMap().norm();
		if (n > 1e-6f)
			q.getNormalVector3fMap() /= n;
	}
	return out;
}

PclIcpResult pclIcp(const PclCloud::Ptr &model, const PclCloud::Ptr &scene, const Eigen::Matrix4f &init,
		    double diameter, const PclIcpParams &params)
{
	pcl::IterativeClosestPoint<pcl::PointNormal, pcl::PointNormal> icp;
	icp.setInputSource(scene);
	icp.setInputTarget(model);
	icp.setMaxCorrespondenceDistance(params.maxCorrespondence * diameter);
	icp.setMaximumIterations(params.iterations);
	icp.setTransformationEpsilon(1e-8);
	icp.setEuclideanFitnessEpsilon(1e-6);
	PclCloud aligned;
	const Eigen::Matrix4f initInv = init.inverse();
	icp.align(aligned, initInv);
	PclIcpResult r;
	r.converged = icp.hasConverged();
	r.pose = icp.getFinalTransformation().inverse();
	r.fitness = icp.getFitnessScore(params.maxCorrespondence * diameter);
	return r;
}

Pose toPose(const Eigen::Matrix4f &m)
{
	Pose p;
	p.R = m.block<3, 3>(0, 0).cast<double>();
	p.t = m.block<3, 1>(0, 3).cast<double>();
	return p;
}

} // namespace ihf::peers
