// SPDX-License-Identifier: MIT
#pragma once

// A peer pose estimator (another library's method) behind one small
// interface, so every peer sees the same model points and the same crop.
// Units are millimetres throughout; poses are model-to-camera (BOP).

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/expected.h"
#include "core/features/cloud_point.h"
#include "core/geometry/pose.h"

namespace ihf::peers {

// Points sampled on the model's surface, model frame, outward unit normals.
struct PeerModel {
	int objId = 0;
	double diameter = 0; // mm, from models_info.json
	std::vector<Eigen::Vector3f> points;
	std::vector<Eigen::Vector3f> normals;
};

struct PeerEstimate {
	bool found = false;
	Pose pose;
	double score = 0;   // the peer's own confidence (higher is better)
	std::string reason; // why there is no pose
};

class Peer
{
public:
	virtual ~Peer() = default;
	virtual const char *name() const = 0;
	// Builds the per-object model (training, features); timed apart.
	virtual Status prepare(const PeerModel &model) = 0;
	// One box: the crop's points with camera-oriented normals (only points
	// that have a normal). Library exceptions are caught and turned into
	// a missing pose.
	virtual PeerEstimate estimate(int objId, std::span<const CloudPoint> scene) = 0;
};

} // namespace ihf::peers
