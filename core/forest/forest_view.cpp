// SPDX-License-Identifier: MIT
#include "core/forest/forest_view.h"

#include <algorithm>
#include <cmath>

namespace ihf {

namespace {

int16_t clamp16(float v)
{
	return static_cast<int16_t>(std::clamp(std::lround(v), -32767l, 32767l));
}

} // namespace

Vote PackedVote::unpack() const
{
	Vote v;
	v.offset = Eigen::Vector3f(offset[0], offset[1], offset[2]);
	// Normalised with the sum in a fixed order: Eigen's 4-float reduction
	// adds in another order with SIMD (amd64, aarch64) than without (armhf),
	// and the votes must be the same bits on every target.
	const float x = rotation[0], y = rotation[1], z = rotation[2], w = rotation[3];
	const float norm = std::sqrt(((x * x + y * y) + z * z) + w * w);
	v.rotation = norm > 0.0f ? Eigen::Quaternionf(w / norm, x / norm, y / norm, z / norm)
				 : Eigen::Quaternionf::Identity();
	return v;
}

PackedVote PackedVote::pack(const Vote &v)
{
	PackedVote p{};
	for (int i = 0; i < 3; ++i)
		p.offset[i] = clamp16(v.offset[i]);
	Eigen::Quaternionf q = v.rotation.normalized();
	p.rotation[0] = clamp16(q.x() * 32767.0f);
	p.rotation[1] = clamp16(q.y() * 32767.0f);
	p.rotation[2] = clamp16(q.z() * 32767.0f);
	p.rotation[3] = clamp16(q.w() * 32767.0f);
	return p;
}

ForestStorage::ForestStorage(const HoughForest &forest, TemplateEncoding encoding)
{
	view_.dims = forest.dims;
	view_.encoding = encoding;
	for (const auto &t : forest.trees) {
		Tree tree;
		tree.nodes = t.nodes;
		if (encoding == TemplateEncoding::kFloat32) {
			tree.templatesF = t.templates;
		} else {
			tree.templatesQ.resize(t.templates.size());
			std::transform(t.templates.begin(), t.templates.end(), tree.templatesQ.begin(),
				       quantiseBin);
		}
		tree.votes.reserve(t.votes.size());
		for (const auto &v : t.votes)
			tree.votes.push_back(PackedVote::pack(v));
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
		v.votes = t.votes;
		treeViews_.push_back(v);
	}
	view_.trees = treeViews_;
}

} // namespace ihf
