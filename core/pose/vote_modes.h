// SPDX-License-Identifier: MIT
#pragma once

// Mode finding over Hough votes (paper Eq. 8 and 13: the argmax of the vote
// density). Translation first: mean-shift with a Gaussian kernel from a set
// of seeds, modes merged and ranked by density. Then, for each translation
// mode, the rotation mode among the votes near it: mean-shift on unit
// quaternions with a geodesic Gaussian kernel, and a weighted quaternion
// average (Markley) of the converged cluster. Caller-provided buffers only.

#include <cstddef>
#include <cstdint>
#include <span>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/runtime/worker_pool.h"

namespace ihf {

struct CastVote {
	Eigen::Vector3f centre; // voted object origin, camera frame, mm
	Eigen::Quaternionf rotation;
	float weight = 1.0f;
};

struct VoteModeConfig {
	float translationBandwidth = 12.0f; // mm, Gaussian sigma
	float rotationBandwidth = 0.26f; // radians, geodesic Gaussian sigma (~15 deg)
	float supportRadius = 2.5f; // in bandwidths: votes nearer a mode support it
	int maxSeeds = 64;
	int maxIterations = 20;
	float mergeDistance = 0.5f; // in translation bandwidths
	// The translation mean shift runs on at most this many votes, an even
	// stride over the positive ones, each weighing for the votes it stands
	// for (0: all). A large object's box casts ~100k votes, most of them
	// within the 27 cells a step visits; the density they describe is as
	// smooth with a sixth of them. The rotation modes use every vote.
	int maxShiftVotes = 0;
	// Distinct rotation modes kept per translation mode (a part seen from
	// two symmetric-looking sides votes for both; the renderer decides).
	int rotationModesPerCentre = 1; // at most 16
};

struct PoseMode {
	Eigen::Vector3f centre = Eigen::Vector3f::Zero();
	Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
	float translationDensity = 0; // kernel-weighted vote mass at the centre
	float rotationDensity = 0; // of the supporting votes, at the rotation
	float supportWeight = 0; // total weight of votes within the support
};

// Scratch for findPoseModes: sized once for the maximum vote count.
struct VoteModeWorkspace {
	std::span<float> scratch; // >= votes
	std::span<Eigen::Vector3f> seeds; // >= maxSeeds
	std::span<uint32_t> support; // >= votes (supporting votes of a centre)
	std::span<Eigen::Vector4f> packed; // >= votes (centres and weights in grid order)
	// With a pool the seeds and the rotation modes are spread over its
	// threads (the same modes as one thread); threads other than the
	// caller's need scratch and support of their own.
	WorkerPool *pool = nullptr;
	std::span<float> threadScratch{};    // >= (threads - 1) x votes
	std::span<uint32_t> threadSupport{}; // >= (threads - 1) x votes
};

// Writes up to modes.size() modes ranked by translation density, each
// translation mode followed by its rotation modes (densest first); returns
// how many. Votes with weight <= 0 are ignored.
size_t findPoseModes(std::span<const CastVote> votes, const VoteModeConfig &config,
		     VoteModeWorkspace workspace, std::span<PoseMode> modes);

// Weighted average of quaternions (Markley et al. 2007): the eigenvector of
// the largest eigenvalue of sum w q q^T. Sign-invariant.
Eigen::Quaternionf averageQuaternion(std::span<const Eigen::Quaternionf> qs,
				    std::span<const float> weights);

} // namespace ihf
