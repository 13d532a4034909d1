// SPDX-License-Identifier: MIT
#pragma once

// Open3D 0.16 global registration as in its tutorial: voxel downsampling,
// FPFH, RANSAC on feature matches with edge-length and distance checkers,
// then point-to-plane ICP on finer clouds.

#include <map>
#include <memory>

#include "benchmarks/peers/peer.h"

namespace ihf::peers {

struct Open3dParams {
	double voxel = 0.05;            // relative to the diameter
	double normalRadius = 0.1;      // unused with given normals; kept for the record
	double featureRadius = 0.25;    // FPFH radius, relative to the diameter (5 voxels)
	int featureMaxNn = 100;
	double ransacDistance = 0.075;  // relative to the diameter (1.5 voxels)
	int ransacIterations = 100000;
	double ransacConfidence = 0.999;
	double edgeLength = 0.9;
	double icpVoxel = 1.0 / 40.0;   // relative to the diameter
	double icpDistance = 0.05;      // relative to the diameter
	int icpIterations = 30;
	int seed = 1;
};

class Open3dPeer : public Peer
{
public:
	explicit Open3dPeer(const Open3dParams &params);
	~Open3dPeer() override;
	const char *name() const override { return "open3d_fpfh"; }
	Status prepare(const PeerModel &model) override;
	PeerEstimate estimate(int objId, std::span<const CloudPoint> scene) override;

private:
	struct Prepared;
	Open3dParams params_;
	std::map<int, std::unique_ptr<Prepared>> models_;
};

} // namespace ihf::peers
