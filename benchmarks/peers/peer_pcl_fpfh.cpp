// SPDX-License-Identifier: MIT
#include "benchmarks/peers/peer_pcl_fpfh.h"

#include <exception>

#include <pcl/features/fpfh.h>
#include <pcl/registration/sample_consensus_prerejective.h>
#include <pcl/search/kdtree.h>

namespace ihf::peers {

namespace {

using Features = pcl::PointCloud<pcl::FPFHSignature33>;

Features::Ptr fpfh(const PclCloud::Ptr &cloud, double radius)
{
	pcl::FPFHEstimation<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> est;
	est.setInputCloud(cloud);
	est.setInputNormals(cloud);
	est.setSearchMethod(pcl::search::KdTree<pcl::PointNormal>::Ptr(new pcl::search::KdTree<pcl::PointNormal>));
	est.setRadiusSearch(radius);
	Features::Ptr f(new Features);
	est.compute(*f);
	return f;
}

} // namespace

Status PclFpfhPeer::prepare(const PeerModel &model)
{
	Prepared p;
	p.diameter = model.diameter;
	PclCloud::Ptr full = toPcl(model);
	p.coarse = voxelDown(full, static_cast<float>(params_.leaf * model.diameter));
	p.fine = voxelDown(full, static_cast<float>(params_.icpLeaf * model.diameter));
	try {
		p.features = fpfh(p.coarse, params_.featureRadius * model.diameter);
	} catch (const std::exception &e) {
		return makeError(Errc::kInvalidArgument, std::string("PCL FPFH: ") + e.what());
	}
	if (p.coarse->size() < 10)
		return makeError(Errc::kInvalidArgument, "model cloud too small");
	models_[model.objId] = std::move(p);
	return {};
}

PeerEstimate PclFpfhPeer::estimate(int objId, std::span<const CloudPoint> scene)
{
	PeerEstimate out;
	auto it = models_.find(objId);
	if (it == models_.end()) {
		out.reason = "no model";
		return out;
	}
	const Prepared &m = it->second;
	try {
		PclCloud::Ptr full = toPcl(scene);
		PclCloud::Ptr crop = voxelDown(full, static_cast<float>(params_.leaf * m.diameter));
		if (crop->size() < 10) {
			out.reason = "fewer than 10 points in the crop";
			return out;
		}
		Features::Ptr cropFeatures = fpfh(crop, params_.featureRadius * m.diameter);

		pcl::SampleConsensusPrerejective<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> align;
		align.setInputSource(m.coarse);
		align.setSourceFeatures(m.features);
		align.setInputTarget(crop);
		align.setTargetFeatures(cropFeatures);
		align.setMaximumIterations(params_.iterations);
		align.setNumberOfSamples(3);
		align.setCorrespondenceRandomness(params_.correspondenceRandomness);
		align.setSimilarityThreshold(params_.similarity);
		align.setMaxCorrespondenceDistance(params_.maxCorrespondence * m.diameter);
		align.setInlierFraction(params_.inlierFraction);
		PclCloud aligned;
		align.align(aligned);
		if (!align.hasConverged()) {
			out.reason = "RANSAC found no pose with enough inliers";
			return out;
		}
		const double inliers = static_cast<double>(align.getInliers().size()) /
				       static_cast<double>(m.coarse->size());
		PclCloud::Ptr fineCrop = voxelDown(full, static_cast<float>(params_.icpLeaf * m.diameter));
		PclIcpResult r = pclIcp(m.fine, fineCrop, align.getFinalTransformation(), m.diameter, params_.icp);
		out.pose = toPose(r.converged ? r.pose : align.getFinalTransformation());
		out.score = inliers;
		out.found = true;
	} catch (const std::exception &e) {
		out.reason = std::string("PCL: ") + e.what();
	}
	return out;
}

} // namespace ihf::peers
