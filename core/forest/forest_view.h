// SPDX-License-Identifier: MIT
#pragma once

// What inference walks: spans over one forest's nodes, templates and votes,
// either owned by a ForestStorage (after training) or pointing straight into
// an mmap-ed forest file. Templates are float or 8-bit quantised (value / 255
// of an L2-normalised histogram, whose entries lie in [0, 1]); votes are
// packed: offsets in whole millimetres, quaternions scaled by 32767.

#include <cstdint>
#include <span>
#include <vector>

#include "core/forest/hough_forest.h"

namespace ihf {

struct PackedVote {
	int16_t offset[3]; // mm
	int16_t rotation[4]; // x, y, z, w * 32767
	int16_t pad = 0;

	Vote unpack() const;
	static PackedVote pack(const Vote &v);
};
static_assert(sizeof(PackedVote) == 16);
static_assert(sizeof(TreeNode) == 32);

enum class TemplateEncoding : uint32_t {
	kFloat32 = 0,
	kUint8 = 1,
};

struct TreeView {
	std::span<const TreeNode> nodes;
	const void *templates = nullptr; // dims entries per template
	std::span<const PackedVote> votes;
};

struct ForestView {
	int dims = 0;
	TemplateEncoding encoding = TemplateEncoding::kFloat32;
	std::span<const TreeView> trees;
};

// Owning, packed copy of a trained forest (votes packed, templates in the
// chosen encoding) and the view over it.
class ForestStorage
{
public:
	ForestStorage() = default;
	ForestStorage(const HoughForest &forest, TemplateEncoding encoding);
	ForestStorage(const ForestStorage &) = delete;
	ForestStorage &operator=(const ForestStorage &) = delete;
	ForestStorage(ForestStorage &&) = default;
	ForestStorage &operator=(ForestStorage &&) = default;

	const ForestView &view() const { return view_; }

	// Raw per-tree buffers, for writing files.
	struct Tree {
		std::vector<TreeNode> nodes;
		std::vector<float> templatesF;
		std::vector<uint8_t> templatesQ;
		std::vector<PackedVote> votes;
	};
	const std::vector<Tree> &trees() const { return trees_; }

private:
	void rebuildView();

	std::vector<Tree> trees_;
	std::vector<TreeView> treeViews_;
	ForestView view_;
};

inline uint8_t quantiseBin(float v)
{
	float q = v * 255.0f + 0.5f;
	return static_cast<uint8_t>(q < 0 ? 0 : (q > 255.0f ? 255.0f : q));
}

} // namespace ihf
