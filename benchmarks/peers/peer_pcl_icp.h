// SPDX-License-Identifier: MIT
#pragma once

// PCL 1.13 ICP alone, started from the box: the model's centroid is put on
// the crop's centroid pushed a quarter diameter away from the camera (the
// visible surface is the object's front), rotation = identity. The baseline
// of what local registration does without a global search.

#include <map>

#include "benchmarks/peers/pcl_cloud.h"

namespace ihf::peers {

struct PclIcpPeerParams {
	float leaf = 1.0f / 40.0f;       // voxel leaf for model and crop, relative to the diameter
	float depthOffset = 0.25f;       // centroid pushed this far back, relative to the diameter
	PclIcpParams icp{0.1f, 50};
};

class PclIcpPeer : public Peer
{
public:
	explicit PclIcpPeer(const PclIcpPeerParams &params) : params_(params) {}
	const char *name() const override { return "pcl_icp"; }
	Status prepare(const PeerModel &model) override;
	PeerEstimate estimate(int objId, std::span<const CloudPoint> scene) override;

private:
	struct Prepared {
		PclCloud::Ptr cloud;
		Eigen::Vector3f centroid;
		double diameter;
	};
	PclIcpPeerParams params_;
	std::map<int, Prepared> models_;
};

} // namespace ihf::peers
