// SPDX-License-Identifier: MIT
#include "core/estimation/forest_walker.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

namespace ihf {

namespace {

// Squared L2 distance summed in kLanes independent partial sums, combined in
// one fixed order. A single running sum is one dependent add per bin (the
// walk's largest cost); separate lanes let the compiler vectorise without
// reassociating, and every target (SSE, NEON or scalar) computes the same
// bits.
constexpr int kLanes = 8; // the combination below names each lane

template<typename T, typename ToFloat>
float squaredDistanceInLanes(const float *h, const T *t, int d, ToFloat toFloat)
{
	float lane[kLanes] = {};
	int i = 0;
	for (; i + kLanes <= d; i += kLanes) {
		for (int l = 0; l < kLanes; ++l) {
			const float e = h[i + l] - toFloat(t[i + l]);
			lane[l] += e * e;
		}
	}
	float acc = ((lane[0] + lane[4]) + (lane[1] + lane[5])) + ((lane[2] + lane[6]) + (lane[3] + lane[7]));
	for (; i < d; ++i) {
		const float e = h[i] - toFloat(t[i]);
		acc += e * e;
	}
	return acc;
}

// The same sum over a sparse 8-bit record (forest_view.h): the record is
// expanded a chunk of bins at a time (zeros, then the present values
// scattered by their bits, 64 bins to a word so that the scatter loop ends
// rarely) and summed with the dense loop, so an absent bin adds h * h
// exactly as a stored zero did and the bits are the same.
float sparseSquaredDistanceInLanes(const float *h, const uint8_t *record, int d)
{
	constexpr int kChunk = 256; // a multiple of 64
	constexpr float kScale = 1.0f / 255.0f;
	const uint8_t *bits = record;
	const uint8_t *value = record + templateBitmapBytes(d);
	uint8_t dense[kChunk];
	float lane[kLanes] = {};
	const int body = d / kLanes * kLanes;
	for (int c = 0; c < body; c += kChunk) {
		const int n = std::min(kChunk, body - c);
		std::memset(dense, 0, sizeof(dense));
		for (int w = 0; w < n; w += 64) {
			uint64_t present = 0;
			const int bytes = std::min(8, (n - w) / 8);
			for (int k = 0; k < bytes; ++k)
				present |= uint64_t{bits[(c + w) / 8 + k]} << (8 * k);
			for (; present != 0; present &= present - 1)
				dense[w + std::countr_zero(present)] = *value++;
		}
		for (int i = 0; i < n; i += kLanes)
			for (int l = 0; l < kLanes; ++l) {
				const float e = h[c + i + l] - static_cast<float>(dense[i + l]) * kScale;
				lane[l] += e * e;
			}
	}
	float acc = ((lane[0] + lane[4]) + (lane[1] + lane[5])) + ((lane[2] + lane[6]) + (lane[3] + lane[7]));
	for (int i = body; i < d; ++i) {
		const float t = (bits[i / 8] >> (i % 8)) & 1u ? static_cast<float>(*value++) * kScale : 0.0f;
		const float e = h[i] - t;
		acc += e * e;
	}
	return acc;
}

} // namespace

float templateDistance(const ForestView &forest, const TreeView &tree, uint32_t index,
		       std::span<const float> histogram)
{
	const int d = forest.dims;
	float acc;
	if (forest.encoding == TemplateEncoding::kFloat32) {
		const float *t = static_cast<const float *>(tree.templates) + static_cast<size_t>(index) * d;
		acc = squaredDistanceInLanes(histogram.data(), t, d, [](float v) { return v; });
	} else {
		const uint8_t *record = static_cast<const uint8_t *>(tree.templates) + tree.templateOffsets[index];
		acc = sparseSquaredDistanceInLanes(histogram.data(), record, d);
	}
	return std::sqrt(acc);
}

namespace {

// Which of a part's control points pass a node's depth check, as bits (up
// to kMaxBits points; larger parts are not cached).
struct KeptSet {
	static constexpr size_t kMaxBits = 256;
	uint64_t words[kMaxBits / 64] = {};
	bool operator==(const KeptSet &) const = default;
};

KeptSet keptSet(std::span<const PartCp> cps, float lo, float hi)
{
	KeptSet k;
	for (size_t i = 0; i < cps.size(); ++i) {
		const float z = cps[i].rel.z();
		k.words[i / 64] |= static_cast<uint64_t>(z >= lo && z <= hi) << (i % 64);
	}
	return k;
}

} // namespace

size_t castPartVotes(const ForestView &forest, std::span<const PartCp> cps,
		     const Eigen::Vector3f &centreMm, const HocpConfig &hocp, float marginMm,
		     std::span<float> hist, std::span<CastVote> votes, size_t count)
{
	const float treeWeight = 1.0f / static_cast<float>(forest.trees.size());
	// A node's histogram depends only on which points pass its depth
	// check, and along a part's walk the same sets recur: a can part's 58
	// nodes see 27 distinct sets on average (syn200), and every point
	// passes at many of them. The histograms of the last sets seen are
	// kept, one per slot of `hist` (slot 0 for the all-points set, the
	// others round robin), and reused: the same values, not recomputed.
	const size_t dims = static_cast<size_t>(forest.dims);
	const size_t slots = std::min(hist.size() / dims, kMaxHistogramSlots);
	const bool cache = cps.size() <= KeptSet::kMaxBits && slots >= 2;
	KeptSet everything;
	for (size_t i = 0; i < cps.size() && cache; ++i)
		everything.words[i / 64] |= uint64_t{1} << (i % 64);
	std::array<KeptSet, kMaxHistogramSlots> keys;
	bool haveWhole = false;
	size_t filled = 1, next = 1; // slots 1.. in use; the next to (re)fill
	const auto slot = [&](size_t k) { return hist.subspan(k * dims, dims); };
	for (const TreeView &tree : forest.trees) {
		int32_t n = 0;
		while (tree.nodes[n].left >= 0) {
			const TreeNode &node = tree.nodes[n];
			std::span<const float> h = slot(0);
			if (!cache) {
				computeHocpDepthChecked(cps, node.zMin, node.zMax, marginMm, hocp, slot(0));
			} else {
				const KeptSet kept = keptSet(cps, node.zMin - marginMm, node.zMax + marginMm);
				if (kept == everything) {
					if (!haveWhole)
						computeHocpDepthChecked(cps, node.zMin, node.zMax, marginMm, hocp, slot(0));
					haveWhole = true;
				} else {
					size_t k = 1;
					while (k < filled && !(keys[k] == kept))
						++k;
					if (k == filled) { // not kept: computed into the next slot
						k = next;
						computeHocpDepthChecked(cps, node.zMin, node.zMax, marginMm, hocp, slot(k));
						keys[k] = kept;
						filled = std::max(filled, k + 1);
						next = next + 1 < slots ? next + 1 : 1;
					}
					h = slot(k);
				}
			}
			float dist = templateDistance(forest, tree, node.templateIndex, h);
			n = dist < node.threshold ? node.left : node.right;
		}
		const TreeNode &leaf = tree.nodes[n];
		if (leaf.voteCount == 0)
			continue;
		const float w = treeWeight / static_cast<float>(leaf.voteCount);
		for (uint32_t i = 0; i < leaf.voteCount && count < votes.size(); ++i) {
			Vote v = tree.votes[leaf.voteBegin + i].unpack(forest.rotations);
			votes[count++] = CastVote{centreMm + v.offset, v.rotation, w};
		}
	}
	return count;
}

} // namespace ihf
