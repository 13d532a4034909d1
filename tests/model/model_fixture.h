// SPDX-License-Identifier: MIT
#pragma once

// Shared by the forest file tests: a random but valid Hough forest built by
// hand (children always after their parent, templates and votes consistent),
// parameters with every field off its default, a small mesh, and raw byte
// surgery on saved files that follows the documented layout on its own (it
// does not use the library's format code), so the tests check the format
// rather than the reader against itself.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "core/forest/hough_forest.h"
#include "core/geometry/mesh.h"
#include "core/model/model_params.h"

namespace ihf::test {

// Parameters with every field set away from its default. kSignSplit with
// 3 x 4 x 4 bins gives dims 96.
inline ModelParams makeParams()
{
	ModelParams p;
	p.objId = 6;
	p.diameter = 217.14256;
	p.symmetric = true;
	p.cloud.normalStep = 3;
	p.cloud.maxJumpMm = 12.5f;
	p.cloud.maxJumpRel = 0.03f;
	p.cloud.pixelStride = 2;
	p.ibs.n = 64;
	p.ibs.solver = IbsSolver::kMultilevelBa;
	p.ibs.offsetCells = 0.3f;
	p.ibs.offsetValue = 0.7f;
	p.ibs.maxPoints = 2500;
	p.ibs.warmStart = IbsWarmStart::kPrevious;
	p.ibs.cgMaxIterations = 17;
	p.ibs.cgTolerance = 2.5e-4f;
	p.ibs.smoothness = 0.1f / 3.0f; // not a short decimal
	p.ibs.ridge = 1e-5f;
	p.ibs.mbaLevels = 4;
	p.parts.kind = PartKind::kFixed;
	p.parts.stride = 6;
	p.parts.fixedFraction = 0.4f;
	p.parts.variableSide = 0.6f;
	p.parts.depthMarginCells = 1.5f;
	p.parts.maxControlPoints = 300;
	p.parts.cap = PartCap::kLargestWeight;
	p.parts.minDataPoints = 20;
	p.hocp.nR = 3;
	p.hocp.nTheta = 4;
	p.hocp.nPhi = 4;
	p.hocp.rMinFraction = 0.07f;
	p.hocp.weighting = HocpWeighting::kSignSplit;
	p.depthCheckMarginMm = 4.25f;
	p.trainScales = {0.9f, 1.0f, 1.1f};
	p.trainViews = 642;
	p.trainSamples = 123456;
	p.trainSeconds = 3601.75;
	p.seed = 18446744073709551557ull; // above 2^63
	p.meshName = "obj_000006.ply";
	return p;
}

inline constexpr int kFixtureDims = 96;

// A small closed mesh: a cube, with per-vertex normals.
inline Mesh makeMesh(bool normals = true)
{
	Mesh m;
	for (int i = 0; i < 8; ++i)
		m.vertices.emplace_back(i & 1 ? 40.0f : -40.0f, i & 2 ? 30.5f : -30.5f,
					i & 4 ? 20.25f : -20.25f);
	const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
				   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
	for (const auto &face : f)
		m.faces.push_back({face[0], face[1], face[2]});
	if (normals)
		for (const auto &v : m.vertices)
			m.normals.push_back(v.normalized());
	return m;
}

// Random tree: nodes appended breadth-first, so children come after their
// parent; every split gets its own template; leaves own consecutive votes.
inline HoughTree makeTree(int dims, int maxDepth, std::mt19937_64 &rng)
{
	std::uniform_real_distribution<float> u01(0.0f, 1.0f);
	std::uniform_real_distribution<float> off(-250.0f, 250.0f);
	std::normal_distribution<float> gauss;
	HoughTree t;
	std::vector<int> depth{1};
	t.nodes.emplace_back();
	for (size_t i = 0; i < t.nodes.size(); ++i) {
		// The top two levels always split, so every tree has inner splits.
		const bool split = depth[i] < maxDepth && (depth[i] <= 2 || u01(rng) < 0.6f);
		if (split) {
			TreeNode &n = t.nodes[i];
			n.left = static_cast<int32_t>(t.nodes.size());
			n.right = n.left + 1;
			n.templateIndex = static_cast<uint32_t>(t.templates.size() / dims);
			n.threshold = 0.2f + u01(rng);
			n.zMin = -u01(rng);
			n.zMax = u01(rng);
			std::vector<float> h(dims);
			float norm = 0;
			for (float &v : h) {
				v = u01(rng) < 0.3f ? 0.0f : u01(rng);
				norm += v * v;
			}
			for (float &v : h)
				t.templates.push_back(norm > 0 ? v / std::sqrt(norm) : 0.0f);
			t.nodes.emplace_back();
			t.nodes.emplace_back();
			depth.push_back(depth[i] + 1);
			depth.push_back(depth[i] + 1);
		} else {
			TreeNode &n = t.nodes[i];
			n.voteBegin = static_cast<uint32_t>(t.votes.size());
			n.voteCount = static_cast<uint32_t>(rng() % 6);
			for (uint32_t k = 0; k < n.voteCount; ++k) {
				// One draw per declarator: the order of function arguments
				// is unspecified (GCC differs between amd64 and aarch64),
				// and the golden file test needs the same forest everywhere.
				const float ox = off(rng), oy = off(rng), oz = off(rng);
				const float qw = gauss(rng), qx = gauss(rng), qy = gauss(rng), qz = gauss(rng);
				Vote v;
				v.offset = Eigen::Vector3f(ox, oy, oz);
				v.rotation = Eigen::Quaternionf(qw, qx, qy, qz).normalized();
				t.votes.push_back(v);
			}
		}
	}
	return t;
}

inline HoughForest makeForest(int trees, int maxDepth, uint64_t seed, int dims = kFixtureDims)
{
	std::mt19937_64 rng(seed);
	HoughForest f;
	f.dims = dims;
	for (int i = 0; i < trees; ++i)
		f.trees.push_back(makeTree(dims, maxDepth, rng));
	return f;
}

// Field by field, floats bit-exactly (== on the values).
inline void expectParamsEqual(const ModelParams &a, const ModelParams &b)
{
	EXPECT_EQ(a.objId, b.objId);
	EXPECT_EQ(a.diameter, b.diameter);
	EXPECT_EQ(a.symmetric, b.symmetric);
	EXPECT_EQ(a.cloud.normalStep, b.cloud.normalStep);
	EXPECT_EQ(a.cloud.maxJumpMm, b.cloud.maxJumpMm);
	EXPECT_EQ(a.cloud.maxJumpRel, b.cloud.maxJumpRel);
	EXPECT_EQ(a.cloud.pixelStride, b.cloud.pixelStride);
	EXPECT_EQ(a.ibs.n, b.ibs.n);
	EXPECT_EQ(a.ibs.solver, b.ibs.solver);
	EXPECT_EQ(a.ibs.offsetCells, b.ibs.offsetCells);
	EXPECT_EQ(a.ibs.offsetValue, b.ibs.offsetValue);
	EXPECT_EQ(a.ibs.maxPoints, b.ibs.maxPoints);
	EXPECT_EQ(a.ibs.warmStart, b.ibs.warmStart);
	EXPECT_EQ(a.ibs.cgMaxIterations, b.ibs.cgMaxIterations);
	EXPECT_EQ(a.ibs.cgTolerance, b.ibs.cgTolerance);
	EXPECT_EQ(a.ibs.smoothness, b.ibs.smoothness);
	EXPECT_EQ(a.ibs.ridge, b.ibs.ridge);
	EXPECT_EQ(a.ibs.mbaLevels, b.ibs.mbaLevels);
	EXPECT_EQ(a.parts.kind, b.parts.kind);
	EXPECT_EQ(a.parts.stride, b.parts.stride);
	EXPECT_EQ(a.parts.fixedFraction, b.parts.fixedFraction);
	EXPECT_EQ(a.parts.variableSide, b.parts.variableSide);
	EXPECT_EQ(a.parts.depthMarginCells, b.parts.depthMarginCells);
	EXPECT_EQ(a.parts.maxControlPoints, b.parts.maxControlPoints);
	EXPECT_EQ(a.parts.cap, b.parts.cap);
	EXPECT_EQ(a.parts.minDataPoints, b.parts.minDataPoints);
	EXPECT_EQ(a.hocp.nR, b.hocp.nR);
	EXPECT_EQ(a.hocp.nTheta, b.hocp.nTheta);
	EXPECT_EQ(a.hocp.nPhi, b.hocp.nPhi);
	EXPECT_EQ(a.hocp.rMinFraction, b.hocp.rMinFraction);
	EXPECT_EQ(a.hocp.weighting, b.hocp.weighting);
	EXPECT_EQ(a.depthCheckMarginMm, b.depthCheckMarginMm);
	EXPECT_EQ(a.trainScales, b.trainScales);
	EXPECT_EQ(a.trainViews, b.trainViews);
	EXPECT_EQ(a.trainSamples, b.trainSamples);
	EXPECT_EQ(a.trainSeconds, b.trainSeconds);
	EXPECT_EQ(a.seed, b.seed);
	EXPECT_EQ(a.meshName, b.meshName);
}

// --- Raw file access by the documented layout (forest_file.h). ---

using Bytes = std::vector<uint8_t>;

inline Bytes readBytes(const std::filesystem::path &p)
{
	std::ifstream in(p, std::ios::binary);
	return Bytes(std::istreambuf_iterator<char>(in), {});
}

inline void writeBytes(const std::filesystem::path &p, const Bytes &b)
{
	std::ofstream out(p, std::ios::binary | std::ios::trunc);
	out.write(reinterpret_cast<const char *>(b.data()), static_cast<std::streamsize>(b.size()));
}

inline uint32_t rd32(const Bytes &b, size_t at)
{
	return b[at] | b[at + 1] << 8 | b[at + 2] << 16 | static_cast<uint32_t>(b[at + 3]) << 24;
}

inline uint64_t rd64(const Bytes &b, size_t at)
{
	return rd32(b, at) | static_cast<uint64_t>(rd32(b, at + 4)) << 32;
}

inline void wr32(Bytes &b, size_t at, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		b[at + i] = static_cast<uint8_t>(v >> (8 * i));
}

inline uint32_t crcOf(const uint8_t *p, size_t n)
{
	return static_cast<uint32_t>(crc32(0L, p, static_cast<uInt>(n)));
}

struct RawEntry {
	size_t at; // where the entry sits in the file
	uint32_t type, tree;
	uint64_t offset, size;
	uint32_t elementSize, elementCount, crc;
};

inline std::vector<RawEntry> rawEntries(const Bytes &b)
{
	std::vector<RawEntry> out;
	const uint32_t count = rd32(b, 20);
	for (uint32_t i = 0; i < count; ++i) {
		size_t at = 64 + 48 * size_t{i};
		out.push_back({at, rd32(b, at), rd32(b, at + 4), rd64(b, at + 8), rd64(b, at + 16),
			       rd32(b, at + 24), rd32(b, at + 28), rd32(b, at + 32)});
	}
	return out;
}

inline const RawEntry *findEntry(const std::vector<RawEntry> &entries, uint32_t type,
				 uint32_t tree = 0)
{
	for (const auto &e : entries)
		if (e.type == type && e.tree == tree)
			return &e;
	return nullptr;
}
// The result points into the list: a temporary list would leave it dangling.
const RawEntry *findEntry(std::vector<RawEntry> &&entries, uint32_t type, uint32_t tree = 0) = delete;

// Recomputes every section CRC, the table CRC and the header CRC, so a
// forged payload passes the checksums and reaches the structural checks. A
// section forged to run past the end of the file keeps its CRC: there are
// no bytes to compute it over (the loader refuses it on its bounds).
inline void resealCrcs(Bytes &b)
{
	const uint32_t count = rd32(b, 20);
	for (const RawEntry &e : rawEntries(b))
		if (e.offset <= b.size() && e.size <= b.size() - e.offset)
			wr32(b, e.at + 32, crcOf(b.data() + e.offset, e.size));
	wr32(b, 36, crcOf(b.data() + 64, 48 * size_t{count}));
	wr32(b, 32, 0);
	wr32(b, 32, crcOf(b.data(), 64));
}

// Section type numbers from forest_file.h, spelled out independently.
inline constexpr uint32_t kRawParams = 1, kRawForest = 2, kRawVertices = 3, kRawFaces = 4,
			  kRawNormals = 5, kRawRotations = 6, kRawNodes = 16, kRawTemplates = 17,
			  kRawVotes = 18, kRawTemplateOffsets = 19;

} // namespace ihf::test
