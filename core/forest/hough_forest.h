// SPDX-License-Identifier: MIT
#pragma once

// The Hough forest of the IHF (paper Sect. III-B), in its in-memory float
// form: what training produces and what inference walks. Split nodes hold a
// template part (its HoCP histogram and relative depth range) and a
// threshold; a part goes left when the L2 distance between its depth-checked
// histogram and the template is below the threshold. Leaves hold the votes
// of the training parts that reached them: the offset from the part centre
// to the object origin (camera frame, mm) and the object rotation.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ihf {

struct Vote {
	Eigen::Vector3f offset = Eigen::Vector3f::Zero(); // part centre -> object origin, mm
	Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity(); // model -> camera
};

struct TreeNode {
	// Split: children indices; leaf: left == -1.
	int32_t left = -1;
	int32_t right = -1;
	// Split payload: template histogram index (into HoughTree::templates,
	// in units of the descriptor dimension), threshold and the template's
	// relative depth range used by the depth check.
	uint32_t templateIndex = 0;
	float threshold = 0;
	float zMin = 0;
	float zMax = 0;
	// Leaf payload: votes [voteBegin, voteBegin + voteCount).
	uint32_t voteBegin = 0;
	uint32_t voteCount = 0;

	bool isLeaf() const { return left < 0; }
};

struct HoughTree {
	std::vector<TreeNode> nodes; // nodes[0] is the root
	std::vector<float> templates; // dims floats per split node template
	std::vector<Vote> votes;

	int depth() const;
	size_t leafCount() const;
};

struct HoughForest {
	int dims = 0; // descriptor dimension d
	std::vector<HoughTree> trees;

	size_t nodeCount() const;
	size_t voteCount() const;
};

} // namespace ihf
