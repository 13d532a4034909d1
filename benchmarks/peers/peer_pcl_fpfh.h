// SPDX-License-Identifier: MIT
#pragma once

// PCL 1.13 global registration: FPFH features on voxel-downsampled clouds
// (the given normals), SampleConsensusPrerejective (Buch et al. 2013), then
// the same ICP polish as the ICP peer.

#include <map>

#include <pcl/point_types.h>

#include "benchmarks/peers/pcl_cloud.h"

namespace ihf::peers {

struct PclFpfhParams {
	float leaf = 0.05f;            // voxel leaf, relative to the diameter
	float featureRadius = 0.25f;   // FPFH radius, relative to the diameter (5 leaves)
	int iterations = 50000;        // RANSAC iterations (PCL tutorial)
	int correspondenceRandomness = 5;
	float similarity = 0.9f;       // edge-length prerejection
	float maxCorrespondence = 0.125f; // inlier distance, relative to the diameter (2.5 leaves, PCL tutorial)
	float inlierFraction = 0.25f;  // of the model's points (PCL tutorial; a view shows at most about half)
	PclIcpParams icp{0.05f, 30};
	float icpLeaf = 1.0f / 40.0f;
};

class PclFpfhPeer : public Peer
{
public:
	explicit PclFpfhPeer(const PclFpfhParams &params) : params_(params) {}
	const char *name() const override { return "pcl_fpfh"; }
	Status prepare(const PeerModel &model) override;
	PeerEstimate estimate(int objId, std::span<const CloudPoint> scene) override;

private:
	struct Prepared {
		PclCloud::Ptr coarse;
		pcl::PointCloud<pcl::FPFHSignature33>::Ptr features;
		PclCloud::Ptr fine; // for ICP
		double diameter;
	};
	PclFpfhParams params_;
	std::map<int, Prepared> models_;
};

} // namespace ihf::peers
