// SPDX-License-Identifier: MIT
#include "core/forest/forest_view.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

namespace ihf {

namespace {

int16_t clamp16(float v)
{
	return static_cast<int16_t>(std::clamp(std::lround(v), -32767l, 32767l));
}

} // namespace

Eigen::Quaternionf PackedRotation::unpack() const
{
	// Normalised with the sum in a fixed order: Eigen's 4-float reduction
	// adds in another order with SIMD (amd64, aarch64) than without (armhf),
	// and the votes must be the same bits on every target.
	const float x = q[0], y = q[1], z = q[2], w = q[3];
	const float norm = std::sqrt(((x * x + y * y) + z * z) + w * w);
	return norm > 0.0f ? Eigen::Quaternionf(w / norm, x / norm, y / norm, z / norm)
			   : Eigen::Quaternionf::Identity();
}

PackedRotation PackedRotation::pack(const Eigen::Quaternionf &rotation)
{
	PackedRotation p{};
	const Eigen::Quaternionf n = rotation.normalized();
	p.q[0] = clamp16(n.x() * 32767.0f);
	p.q[1] = clamp16(n.y() * 32767.0f);
	p.q[2] = clamp16(n.z() * 32767.0f);
	p.q[3] = clamp16(n.w() * 32767.0f);
	return p;
}

Vote PackedVote::unpack(std::span<const PackedRotation> rotations) const
{
	Vote v;
	v.offset = Eigen::Vector3f(offset[0], offset[1], offset[2]);
	v.rotation = rotations[rotation].unpack();
	return v;
}

void appendSparseTemplate(std::span<const uint8_t> values, std::vector<uint8_t> &out)
{
	const size_t bitmap = out.size();
	out.resize(out.size() + templateBitmapBytes(static_cast<int>(values.size())), 0);
	for (size_t i = 0; i < values.size(); ++i)
		if (values[i] != 0) {
			out[bitmap + i / 8] |= static_cast<uint8_t>(1u << (i % 8));
			out.push_back(values[i]);
		}
}

void expandSparseTemplate(const uint8_t *record, std::span<uint8_t> out)
{
	const uint8_t *value = record + templateBitmapBytes(static_cast<int>(out.size()));
	for (size_t i = 0; i < out.size(); ++i)
		out[i] = (record[i / 8] >> (i % 8)) & 1u ? *value++ : 0;
}

ForestStorage::ForestStorage(const HoughForest &forest, TemplateEncoding encoding)
{
	view_.dims = forest.dims;
	view_.encoding = encoding;
	// Distinct packed rotations in order of first use, so the same forest
	// always gives the same table.
	std::map<std::array<int16_t, 4>, uint16_t> index;
	std::vector<uint8_t> quantised(static_cast<size_t>(std::max(forest.dims, 0)));
	for (const auto &t : forest.trees) {
		Tree tree;
		tree.nodes = t.nodes;
		if (encoding == TemplateEncoding::kFloat32) {
			tree.templatesF = t.templates;
		} else if (forest.dims > 0) {
			const size_t dims = static_cast<size_t>(forest.dims);
			for (size_t k = 0; k + dims <= t.templates.size(); k += dims) {
				std::transform(t.templates.begin() + static_cast<std::ptrdiff_t>(k),
					       t.templates.begin() + static_cast<std::ptrdiff_t>(k + dims),
					       quantised.begin(), quantiseBin);
				tree.templateOffsets.push_back(static_cast<uint32_t>(tree.templatesQ.size()));
				appendSparseTemplate(quantised, tree.templatesQ);
			}
		}
		tree.votes.reserve(t.votes.size());
		for (const auto &v : t.votes) {
			const PackedRotation r = PackedRotation::pack(v.rotation);
			const std::array<int16_t, 4> key{r.q[0], r.q[1], r.q[2], r.q[3]};
			auto it = index.find(key);
			if (it == index.end()) {
				if (rotations_.size() == kMaxForestRotations) {
					error_ = "the forest's votes have more than " +
						 std::to_string(kMaxForestRotations) + " distinct rotations";
					trees_.clear();
					rotations_.clear();
					rebuildView();
					return;
				}
				it = index.emplace(key, static_cast<uint16_t>(rotations_.size())).first;
				rotations_.push_back(r);
			}
			PackedVote p{};
			for (int i = 0; i < 3; ++i)
				p.offset[i] = clamp16(v.offset[i]);
			p.rotation = it->second;
			tree.votes.push_back(p);
		}
		trees_.push_back(std::move(tree));
	}
	rebuildView();
}

void ForestStorage::rebuildView()
{
	treeViews_.clear();
	for (const auto &t : trees_) {
		TreeView v;
		v.nodes = t.nodes;
		v.templates = view_.encoding == TemplateEncoding::kFloat32
				      ? static_cast<const void *>(t.templatesF.data())
				      : static_cast<const void *>(t.templatesQ.data());
		v.templateOffsets = t.templateOffsets;
		v.votes = t.votes;
		treeViews_.push_back(v);
	}
	view_.rotations = rotations_;
	view_.trees = treeViews_;
}

} // namespace ihf
