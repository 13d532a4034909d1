// SPDX-License-Identifier: MIT
#include "core/model/forest_file_format.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include <zlib.h>

namespace ihf {

const char *sectionTypeName(SectionType type)
{
	switch (type) {
	case SectionType::kParams: return "PARAMS";
	case SectionType::kForest: return "FOREST";
	case SectionType::kMeshVertices: return "MESH_VERTICES";
	case SectionType::kMeshFaces: return "MESH_FACES";
	case SectionType::kMeshNormals: return "MESH_NORMALS";
	case SectionType::kRotations: return "ROTATIONS";
	case SectionType::kNearSymmetries: return "NEAR_SYMMETRIES";
	case SectionType::kTemplateOffsets: return "TEMPLATE_OFFSETS";
	case SectionType::kNodes: return "NODES";
	case SectionType::kTemplates: return "TEMPLATES";
	case SectionType::kVotes: return "VOTES";
	}
	return "UNKNOWN";
}

namespace forestfile {

namespace {

void putF32(std::byte *p, float v)
{
	putU32(p, std::bit_cast<uint32_t>(v));
}

float getF32(const std::byte *p)
{
	return std::bit_cast<float>(getU32(p));
}

} // namespace

void encodeNearSymmetry(const NearSymmetry &s, std::byte *out)
{
	for (int i = 0; i < 3; ++i) {
		putF32(out + 4 * i, s.axis(i));
		putF32(out + 12 + 4 * i, s.point(i));
	}
	putF32(out + 24, s.turnDeg);
	putF32(out + 28, s.differingShare);
}

NearSymmetry decodeNearSymmetry(const std::byte *in)
{
	NearSymmetry s;
	for (int i = 0; i < 3; ++i) {
		s.axis(i) = getF32(in + 4 * i);
		s.point(i) = getF32(in + 12 + 4 * i);
	}
	s.turnDeg = getF32(in + 24);
	s.differingShare = getF32(in + 28);
	s.alikeViews = -1; // not stored
	return s;
}

std::optional<std::string> checkNearSymmetry(const NearSymmetry &s)
{
	if (!s.axis.allFinite() || !s.point.allFinite() || !std::isfinite(s.turnDeg) ||
	    !std::isfinite(s.differingShare))
		return "a number that is not finite";
	if (std::abs(s.axis.norm() - 1.0f) > 1e-3f)
		return "axis of length " + std::to_string(s.axis.norm()) + ", not 1";
	if (s.turnDeg < 0 || s.turnDeg >= 360)
		return "turn " + std::to_string(s.turnDeg) + " deg outside [0, 360)";
	if (s.differingShare < 0 || s.differingShare > 1)
		return "differing share " + std::to_string(s.differingShare) + " outside [0, 1]";
	return std::nullopt;
}

uint32_t crc32Of(const void *data, uint64_t size)
{
	uLong crc = crc32_z(0L, Z_NULL, 0);
	const auto *p = static_cast<const Bytef *>(data);
	// crc32_z takes z_size_t; chunk anyway so any size_t width is safe.
	constexpr uint64_t kChunk = uint64_t{1} << 30;
	while (size > 0) {
		const uint64_t n = std::min(size, kChunk);
		crc = crc32_z(crc, p, static_cast<z_size_t>(n));
		p += n;
		size -= n;
	}
	return static_cast<uint32_t>(crc);
}

void encodeEntry(const ForestFileSection &s, std::byte *out)
{
	std::fill(out, out + kEntrySize, std::byte{0});
	putU32(out + 0, static_cast<uint32_t>(s.type));
	putU32(out + 4, s.tree);
	putU64(out + 8, s.offset);
	putU64(out + 16, s.size);
	putU32(out + 24, s.elementSize);
	putU32(out + 28, s.elementCount);
	putU32(out + 32, s.crc);
}

ForestFileSection decodeEntry(const std::byte *in)
{
	ForestFileSection s;
	s.type = static_cast<SectionType>(getU32(in + 0));
	s.tree = getU32(in + 4);
	s.offset = getU64(in + 8);
	s.size = getU64(in + 16);
	s.elementSize = getU32(in + 24);
	s.elementCount = getU32(in + 28);
	s.crc = getU32(in + 32);
	return s;
}

uint64_t templateBytes(uint64_t dims, TemplateEncoding encoding)
{
	return encoding == TemplateEncoding::kFloat32 ? dims * sizeof(float) : 1;
}

std::optional<std::string> checkSparseTemplates(const uint8_t *data, uint64_t size,
						std::span<const uint32_t> offsets, int dims,
						uint64_t &bins)
{
	const uint64_t bitmap = templateBitmapBytes(dims);
	uint64_t at = 0;
	for (size_t k = 0; k < offsets.size(); ++k) {
		const std::string where = "template " + std::to_string(k) + ": ";
		if (offsets[k] != at)
			return where + "record at byte " + std::to_string(offsets[k]) + ", expected " +
			       std::to_string(at) + " (records are back to back)";
		if (bitmap > size - at)
			return where + "bitmap runs past the end of the templates (" +
			       std::to_string(size) + " bytes)";
		uint64_t present = 0;
		for (uint64_t b = 0; b < bitmap; ++b)
			present += static_cast<uint64_t>(std::popcount(data[at + b]));
		const unsigned tail = static_cast<unsigned>(dims % 8);
		if (tail != 0 && (data[at + bitmap - 1] >> tail) != 0)
			return where + "bits set past the " + std::to_string(dims) + " bins";
		if (present > size - at - bitmap)
			return where + std::to_string(present) +
			       " values run past the end of the templates (" + std::to_string(size) +
			       " bytes)";
		at += bitmap + present;
		bins += present;
	}
	if (at != size)
		return std::to_string(size - at) + " bytes of templates after the last record";
	return std::nullopt;
}

std::optional<std::string> checkVoteRotations(std::span<const PackedVote> votes,
					      uint64_t rotationCount)
{
	for (size_t v = 0; v < votes.size(); ++v)
		if (votes[v].rotation >= rotationCount)
			return "vote " + std::to_string(v) + ": rotation " +
			       std::to_string(votes[v].rotation) + " out of range (" +
			       std::to_string(rotationCount) + " rotations)";
	return std::nullopt;
}

std::optional<std::string> checkTree(std::span<const TreeNode> nodes, uint64_t templateCount,
				     uint64_t voteCount, ForestTreeStats &stats)
{
	stats = ForestTreeStats{};
	if (nodes.empty())
		return std::string("has no nodes (a tree needs at least its root)");
	const int64_t n = static_cast<int64_t>(nodes.size());

	// Children come after their parent, so a node's depth is final by the
	// time the loop reaches it; 0 marks nodes no path from the root reaches.
	std::vector<int> depth(nodes.size(), 0);
	depth[0] = 1;
	for (int64_t i = 0; i < n; ++i) {
		const TreeNode &node = nodes[i];
		const std::string at = "node " + std::to_string(i) + ": ";
		if (node.left == -1 && node.right == -1) {
			if (uint64_t{node.voteBegin} + node.voteCount > voteCount)
				return at + "leaf votes [" + std::to_string(node.voteBegin) + ", " +
				       std::to_string(uint64_t{node.voteBegin} + node.voteCount) +
				       ") outside the tree's " + std::to_string(voteCount) + " votes";
			stats.leaves++;
		} else {
			for (int32_t child : {node.left, node.right}) {
				if (child < 0)
					return at + "child index " + std::to_string(child) +
					       " (a leaf has both children -1, a split neither)";
				if (child <= i)
					return at + "child index " + std::to_string(child) +
					       " points backwards (children must come after their parent)";
				if (child >= n)
					return at + "child index " + std::to_string(child) +
					       " out of range (" + std::to_string(n) + " nodes)";
			}
			if (node.templateIndex >= templateCount)
				return at + "template index " + std::to_string(node.templateIndex) +
				       " out of range (" + std::to_string(templateCount) + " templates)";
			if (!std::isfinite(node.threshold) || !std::isfinite(node.zMin) ||
			    !std::isfinite(node.zMax))
				return at + "non-finite threshold or depth range";
			if (depth[i] > 0) {
				const int d = depth[i] + 1;
				if (d > kMaxTreeDepth)
					return at + "tree deeper than " + std::to_string(kMaxTreeDepth) +
					       " levels";
				depth[node.left] = std::max(depth[node.left], d);
				depth[node.right] = std::max(depth[node.right], d);
			}
		}
		stats.depth = std::max(stats.depth, depth[i]);
	}
	stats.nodes = static_cast<uint32_t>(nodes.size());
	stats.templates = static_cast<uint32_t>(templateCount);
	stats.votes = static_cast<uint32_t>(voteCount);
	return std::nullopt;
}

} // namespace forestfile

} // namespace ihf
