// SPDX-License-Identifier: MIT
#pragma once

// What inference walks: spans over one forest's nodes, templates and votes,
// either owned by a ForestStorage (after training) or pointing straight into
// an mmap-ed forest file. Templates are float or 8-bit quantised (value / 255
// of an L2-normalised histogram, whose entries lie in [0, 1]). A HoCP
// histogram of at most max_control_points points has about three quarters of
// its bins empty, so 8-bit templates are stored sparse: a presence bitmap
// (bit i of byte i / 8 for bin i) followed by the values of the present bins
// in bin order, each tree's records back to back and found by their byte
// offsets. Votes are packed: offsets in whole millimetres and the index of
// the rotation in the forest's table of distinct rotations (quaternions
// scaled by 32767): training votes take their rotations from the training
// views, so a forest has only as many distinct rotations as views.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/forest/hough_forest.h"

namespace ihf {

struct PackedRotation {
	int16_t q[4]; // x, y, z, w * 32767

	Eigen::Quaternionf unpack() const;
	static PackedRotation pack(const Eigen::Quaternionf &q);
	bool operator==(const PackedRotation &) const = default;
};

struct PackedVote {
	int16_t offset[3]; // mm
	uint16_t rotation; // index into ForestView::rotations

	Vote unpack(std::span<const PackedRotation> rotations) const;
};
static_assert(sizeof(PackedRotation) == 8);
static_assert(sizeof(PackedVote) == 8);
static_assert(sizeof(TreeNode) == 32);

// Most distinct rotations a forest can index.
inline constexpr size_t kMaxForestRotations = size_t{1} << 16;

enum class TemplateEncoding : uint32_t {
	kFloat32 = 0,
	kUint8 = 1,
};

// Bytes of a sparse 8-bit template's presence bitmap.
inline size_t templateBitmapBytes(int dims)
{
	return (static_cast<size_t>(dims) + 7) / 8;
}

struct TreeView {
	std::span<const TreeNode> nodes;
	// float32: dims floats per template; uint8: the sparse records.
	const void *templates = nullptr;
	// uint8 only: byte offset of each template's record in `templates`.
	std::span<const uint32_t> templateOffsets;
	std::span<const PackedVote> votes;
};

struct ForestView {
	int dims = 0;
	TemplateEncoding encoding = TemplateEncoding::kFloat32;
	std::span<const PackedRotation> rotations; // what votes index
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
		std::vector<uint8_t> templatesQ; // sparse records
		std::vector<uint32_t> templateOffsets;
		std::vector<PackedVote> votes;
	};
	const std::vector<Tree> &trees() const { return trees_; }
	const std::vector<PackedRotation> &rotations() const { return rotations_; }
	// Empty, or why the forest cannot be packed (more distinct rotations
	// than a vote can index); the view is then empty.
	const std::string &error() const { return error_; }

private:
	void rebuildView();

	std::vector<Tree> trees_;
	std::vector<PackedRotation> rotations_;
	std::string error_;
	std::vector<TreeView> treeViews_;
	ForestView view_;
};

inline uint8_t quantiseBin(float v)
{
	float q = v * 255.0f + 0.5f;
	return static_cast<uint8_t>(q < 0 ? 0 : (q > 255.0f ? 255.0f : q));
}

// Appends the sparse record of one 8-bit template (dims = values.size()).
void appendSparseTemplate(std::span<const uint8_t> values, std::vector<uint8_t> &out);

// The dense 8-bit values of a sparse record (out.size() = dims).
void expandSparseTemplate(const uint8_t *record, std::span<uint8_t> out);

} // namespace ihf
