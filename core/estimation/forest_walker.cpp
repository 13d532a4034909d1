// SPDX-License-Identifier: MIT
#include "core/estimation/forest_walker.h"

#include <cmath>

namespace ihf {

float templateDistance(const ForestView &forest, const TreeView &tree, uint32_t index,
		       std::span<const float> histogram)
{
	const int d = forest.dims;
	float acc = 0;
	if (forest.encoding == TemplateEncoding::kFloat32) {
		const float *t = static_cast<const float *>(tree.templates) + static_cast<size_t>(index) * d;
		for (int i = 0; i < d; ++i) {
			float e = histogram[i] - t[i];
			acc += e * e;
		}
	} else {
		const uint8_t *t = static_cast<const uint8_t *>(tree.templates) + static_cast<size_t>(index) * d;
		constexpr float kScale = 1.0f / 255.0f;
		for (int i = 0; i < d; ++i) {
			float e = histogram[i] - t[i] * kScale;
			acc += e * e;
		}
	}
	return std::sqrt(acc);
}

size_t castPartVotes(const ForestView &forest, std::span<const PartCp> cps,
		     const Eigen::Vector3f &centreMm, const HocpConfig &hocp, float marginMm,
		     std::span<float> hist, std::span<CastVote> votes, size_t count)
{
	const float treeWeight = 1.0f / static_cast<float>(forest.trees.size());
	for (const TreeView &tree : forest.trees) {
		int32_t n = 0;
		while (tree.nodes[n].left >= 0) {
			const TreeNode &node = tree.nodes[n];
			computeHocpDepthChecked(cps, node.zMin, node.zMax, marginMm, hocp, hist);
			float dist = templateDistance(forest, tree, node.templateIndex, hist);
			n = dist < node.threshold ? node.left : node.right;
		}
		const TreeNode &leaf = tree.nodes[n];
		if (leaf.voteCount == 0)
			continue;
		const float w = treeWeight / static_cast<float>(leaf.voteCount);
		for (uint32_t i = 0; i < leaf.voteCount && count < votes.size(); ++i) {
			Vote v = tree.votes[leaf.voteBegin + i].unpack();
			votes[count++] = CastVote{centreMm + v.offset, v.rotation, w};
		}
	}
	return count;
}

} // namespace ihf
