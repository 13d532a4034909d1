// SPDX-License-Identifier: MIT
#include "core/forest/hough_forest.h"

#include <algorithm>

namespace ihf {

int HoughTree::depth() const
{
	if (nodes.empty())
		return 0;
	// Iterative DFS: (node, depth) pairs.
	std::vector<std::pair<int32_t, int>> stack{{0, 1}};
	int best = 0;
	while (!stack.empty()) {
		auto [n, d] = stack.back();
		stack.pop_back();
		best = std::max(best, d);
		if (!nodes[n].isLeaf()) {
			stack.push_back({nodes[n].left, d + 1});
			stack.push_back({nodes[n].right, d + 1});
		}
	}
	return best;
}

size_t HoughTree::leafCount() const
{
	return std::count_if(nodes.begin(), nodes.end(), [](const TreeNode &n) { return n.isLeaf(); });
}

size_t HoughForest::nodeCount() const
{
	size_t n = 0;
	for (const auto &t : trees)
		n += t.nodes.size();
	return n;
}

size_t HoughForest::voteCount() const
{
	size_t n = 0;
	for (const auto &t : trees)
		n += t.votes.size();
	return n;
}

} // namespace ihf
