// SPDX-License-Identifier: MIT
#include "benchmarks/peers/peer_pcl_icp.h"

#include <exception>

namespace ihf::peers {

Status PclIcpPeer::prepare(const PeerModel &model)
{
	Prepared p;
	p.diameter = model.diameter;
	p.cloud = voxelDown(toPcl(model), static_cast<float>(params_.leaf * model.diameter));
	if (p.cloud->empty())
		return makeError(Errc::kInvalidArgument, "empty model cloud");
	p.centroid.setZero();
	for (const auto &q : *p.cloud)
		p.centroid += q.getVector3fMap();
	p.centroid /= static_cast<float>(p.cloud->size());
	models_[model.objId] = std::move(p);
	return {};
}

PeerEstimate PclIcpPeer::estimate(int objId, std::span<const CloudPoint> scene)
{
	PeerEstimate out;
	auto it = models_.find(objId);
	if (it == models_.end()) {
		out.reason = "no model";
		return out;
	}
	const Prepared &m = it->second;
	try {
		PclCloud::Ptr crop = voxelDown(toPcl(scene), static_cast<float>(params_.leaf * m.diameter));
		if (crop->size() < 10) {
			out.reason = "fewer than 10 points in the crop";
			return out;
		}
		Eigen::Vector3f c = Eigen::Vector3f::Zero();
		for (const auto &q : *crop)
			c += q.getVector3fMap();
		c /= static_cast<float>(crop->size());
		c += c.normalized() * static_cast<float>(params_.depthOffset * m.diameter);
		Eigen::Matrix4f init = Eigen::Matrix4f::Identity();
		init.block<3, 1>(0, 3) = c - m.centroid;
		PclIcpResult r = pclIcp(m.cloud, crop, init, m.diameter, params_.icp);
		if (!r.converged) {
			out.reason = "ICP did not converge";
			return out;
		}
		out.pose = toPose(r.pose);
		out.score = 1.0 / (1.0 + r.fitness);
		out.found = true;
	} catch (const std::exception &e) {
		out.reason = std::string("PCL: ") + e.what();
	}
	return out;
}

} // namespace ihf::peers
