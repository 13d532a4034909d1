// SPDX-License-Identifier: MIT
// The forest file: the documented byte layout, exact round trips for both
// template encodings, the view used in place inside the mapping, and every
// kind of damage refused with a message naming the file and the fault.

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/features/hocp.h"
#include "core/forest/forest_view.h"
#include "core/model/forest_file.h"
#include "tests/common/test_paths.h"
#include "tests/model/model_fixture.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;
using test::Bytes;

bool inside(const void *p, std::span<const std::byte> range)
{
	auto *b = static_cast<const std::byte *>(p);
	return b >= range.data() && b < range.data() + range.size();
}

class ForestFileTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		dir_ = test::freshTempDir(std::string("model_") +
					  ::testing::UnitTest::GetInstance()->current_test_info()->name());
		params_ = test::makeParams();
		mesh_ = test::makeMesh();
		forest_ = test::makeForest(3, 7, 42);
		ASSERT_EQ(hocpDimension(params_.hocp), test::kFixtureDims);
	}

	fs::path save(TemplateEncoding enc, const std::string &name = "model.ihf")
	{
		ForestStorage storage(forest_, enc);
		fs::path file = dir_ / name;
		Status s = saveModelFile(file, params_, mesh_, storage.view());
		EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
		return file;
	}

	// Loads a file that must fail; returns the error.
	Error loadError(const fs::path &file)
	{
		auto r = loadModelFile(file);
		EXPECT_FALSE(r.ok()) << file << " loaded";
		if (r.ok())
			return {};
		EXPECT_NE(r.error().message.find(file.string()), std::string::npos)
			<< "error does not name the file: " << r.error().message;
		return r.error();
	}

	// Writes bytes to a fresh file and returns its load error.
	Error loadErrorOf(const Bytes &bytes, const std::string &name = "bad.ihf")
	{
		fs::path file = dir_ / name;
		test::writeBytes(file, bytes);
		return loadError(file);
	}

	fs::path dir_;
	ModelParams params_;
	Mesh mesh_;
	HoughForest forest_;
};

TEST_F(ForestFileTest, LayoutFollowsTheSpec)
{
	const fs::path file = save(TemplateEncoding::kUint8);
	const Bytes b = test::readBytes(file);
	ASSERT_GE(b.size(), 64u);
	EXPECT_EQ(std::string(b.begin(), b.begin() + 8), "IHFOREST");
	EXPECT_EQ(test::rd32(b, 8), 2u); // version
	// Endianness marker 0x01020304 stored little-endian.
	EXPECT_EQ(b[12], 0x04);
	EXPECT_EQ(b[13], 0x03);
	EXPECT_EQ(b[14], 0x02);
	EXPECT_EQ(b[15], 0x01);
	EXPECT_EQ(test::rd32(b, 16), 64u); // header size
	EXPECT_EQ(test::rd64(b, 24), b.size());
	Bytes h(b.begin(), b.begin() + 64);
	test::wr32(h, 32, 0);
	EXPECT_EQ(test::rd32(b, 32), test::crcOf(h.data(), 64));

	const auto entries = test::rawEntries(b);
	// PARAMS, FOREST, vertices, faces, normals, rotations, 4 sections per
	// tree (uint8 templates have offsets).
	ASSERT_EQ(entries.size(), 6u + 4u * forest_.trees.size());
	EXPECT_EQ(test::rd32(b, 36), test::crcOf(b.data() + 64, 48 * entries.size()));
	for (const auto &e : entries) {
		EXPECT_EQ(e.offset % 64, 0u);
		EXPECT_LE(e.offset + e.size, b.size());
		EXPECT_EQ(e.size, uint64_t{e.elementSize} * e.elementCount);
		EXPECT_EQ(e.crc, test::crcOf(b.data() + e.offset, e.size));
	}
	for (uint32_t t = 0; t < forest_.trees.size(); ++t) {
		const HoughTree &tree = forest_.trees[t];
		const auto *nodes = test::findEntry(entries, test::kRawNodes, t);
		const auto *templ = test::findEntry(entries, test::kRawTemplates, t);
		const auto *offsets = test::findEntry(entries, test::kRawTemplateOffsets, t);
		const auto *votes = test::findEntry(entries, test::kRawVotes, t);
		ASSERT_TRUE(nodes && templ && offsets && votes);
		EXPECT_EQ(nodes->elementSize, 32u);
		EXPECT_EQ(nodes->elementCount, tree.nodes.size());
		// Sparse records: a 12-byte bitmap (96 bins) and the non-zero values.
		const size_t templates = tree.templates.size() / 96;
		size_t recordBytes = 0;
		for (size_t k = 0; k < templates; ++k) {
			const uint32_t at = test::rd32(b, offsets->offset + 4 * k);
			EXPECT_EQ(at, recordBytes) << "template " << k;
			size_t present = 0;
			for (size_t i = 0; i < 96; ++i) {
				const uint8_t q = quantiseBin(tree.templates[96 * k + i]);
				const bool bit = (b[templ->offset + at + i / 8] >> (i % 8)) & 1;
				EXPECT_EQ(bit, q != 0) << "template " << k << " bin " << i;
				if (q != 0 && bit) {
					EXPECT_EQ(b[templ->offset + at + 12 + present], q);
				}
				present += q != 0;
			}
			recordBytes += 12 + present;
		}
		EXPECT_EQ(templ->elementSize, 1u);
		EXPECT_EQ(templ->elementCount, recordBytes);
		EXPECT_LT(recordBytes, tree.templates.size()); // smaller than dense uint8
		EXPECT_EQ(offsets->elementSize, 4u);
		EXPECT_EQ(offsets->elementCount, templates);
		EXPECT_EQ(votes->elementSize, 8u);
		EXPECT_EQ(votes->elementCount, tree.votes.size());
		// A node record is the 32-byte little-endian TreeNode.
		const TreeNode &root = tree.nodes[0];
		EXPECT_EQ(static_cast<int32_t>(test::rd32(b, nodes->offset)), root.left);
		EXPECT_EQ(static_cast<int32_t>(test::rd32(b, nodes->offset + 4)), root.right);
	}
	const auto *verts = test::findEntry(entries, test::kRawVertices);
	ASSERT_TRUE(verts);
	float x0;
	std::memcpy(&x0, b.data() + verts->offset, 4);
	EXPECT_EQ(x0, mesh_.vertices[0].x());
	// Faces of a mesh with at most 65536 vertices are u16 x 3.
	const auto *faces = test::findEntry(entries, test::kRawFaces);
	ASSERT_TRUE(faces);
	EXPECT_EQ(faces->elementSize, 6u);
	EXPECT_EQ(faces->elementCount, mesh_.faces.size());
	EXPECT_EQ(b[faces->offset + 6 + 2] | (b[faces->offset + 6 + 3] << 8), mesh_.faces[1][1]);
}

void expectRoundTrip(const HoughForest &forest, TemplateEncoding enc, const ObjectModel &model,
		     const ModelParams &params, const Mesh &mesh)
{
	test::expectParamsEqual(params, model.params());

	const Mesh &m = model.mesh();
	ASSERT_EQ(m.vertices.size(), mesh.vertices.size());
	ASSERT_EQ(m.faces.size(), mesh.faces.size());
	ASSERT_EQ(m.normals.size(), mesh.normals.size());
	for (size_t i = 0; i < mesh.vertices.size(); ++i)
		EXPECT_EQ(m.vertices[i], mesh.vertices[i]);
	for (size_t i = 0; i < mesh.normals.size(); ++i)
		EXPECT_EQ(m.normals[i], mesh.normals[i]);
	for (size_t i = 0; i < mesh.faces.size(); ++i)
		EXPECT_EQ(m.faces[i], mesh.faces[i]);

	const ForestView &v = model.forest();
	EXPECT_EQ(v.dims, forest.dims);
	EXPECT_EQ(v.encoding, enc);
	ASSERT_EQ(v.trees.size(), forest.trees.size());
	for (size_t t = 0; t < forest.trees.size(); ++t) {
		const HoughTree &src = forest.trees[t];
		const TreeView &tv = v.trees[t];
		ASSERT_EQ(tv.nodes.size(), src.nodes.size());
		EXPECT_EQ(std::memcmp(tv.nodes.data(), src.nodes.data(), src.nodes.size() * 32), 0);
		if (enc == TemplateEncoding::kFloat32) {
			EXPECT_EQ(std::memcmp(tv.templates, src.templates.data(),
					      src.templates.size() * sizeof(float)),
				  0);
		} else {
			const size_t dims = static_cast<size_t>(forest.dims);
			ASSERT_EQ(tv.templateOffsets.size(), src.templates.size() / dims);
			std::vector<uint8_t> dense(dims);
			size_t bad = 0;
			for (size_t k = 0; k < tv.templateOffsets.size(); ++k) {
				expandSparseTemplate(static_cast<const uint8_t *>(tv.templates) +
							     tv.templateOffsets[k],
						     dense);
				for (size_t i = 0; i < dims; ++i)
					bad += dense[i] != quantiseBin(src.templates[k * dims + i]);
			}
			EXPECT_EQ(bad, 0u) << "tree " << t;
		}
		ASSERT_EQ(tv.votes.size(), src.votes.size());
		for (size_t i = 0; i < src.votes.size(); ++i) {
			const PackedVote &got = tv.votes[i];
			for (int k = 0; k < 3; ++k)
				EXPECT_EQ(got.offset[k], std::lround(src.votes[i].offset[k]));
			ASSERT_LT(got.rotation, v.rotations.size());
			EXPECT_EQ(v.rotations[got.rotation], PackedRotation::pack(src.votes[i].rotation));
		}
	}
}

TEST_F(ForestFileTest, RoundTripFloat32)
{
	const fs::path file = save(TemplateEncoding::kFloat32);
	auto model = loadModelFile(file);
	ASSERT_TRUE(model.ok()) << model.error().message;
	expectRoundTrip(forest_, TemplateEncoding::kFloat32, **model, params_, mesh_);
}

TEST_F(ForestFileTest, RoundTripUint8)
{
	const fs::path file = save(TemplateEncoding::kUint8);
	auto model = loadModelFile(file);
	ASSERT_TRUE(model.ok()) << model.error().message;
	expectRoundTrip(forest_, TemplateEncoding::kUint8, **model, params_, mesh_);
}

TEST_F(ForestFileTest, MeshWithoutNormals)
{
	mesh_ = test::makeMesh(false);
	const fs::path file = save(TemplateEncoding::kFloat32);
	auto model = loadModelFile(file);
	ASSERT_TRUE(model.ok()) << model.error().message;
	EXPECT_FALSE((*model)->mesh().hasNormals());
	EXPECT_EQ(test::rawEntries(test::readBytes(file)).size(), 5u + 3u * forest_.trees.size());
	expectRoundTrip(forest_, TemplateEncoding::kFloat32, **model, params_, mesh_);
}

// Past 65536 vertices a face index needs 32 bits; at 65536 it fits 16.
TEST_F(ForestFileTest, FaceIndexWidthFollowsTheVertexCount)
{
	for (size_t vertices : {size_t{65536}, size_t{65537}}) {
		mesh_.normals.clear();
		mesh_.vertices.resize(vertices, Eigen::Vector3f(1, 2, 3));
		mesh_.faces = {{0, 1, 2}, {uint32_t(vertices - 3), uint32_t(vertices - 2), uint32_t(vertices - 1)}};
		const fs::path file = save(TemplateEncoding::kUint8, "big.ihf");
		const auto entries = test::rawEntries(test::readBytes(file));
		const auto *faces = test::findEntry(entries, test::kRawFaces);
		ASSERT_TRUE(faces);
		EXPECT_EQ(faces->elementSize, vertices <= 65536 ? 6u : 12u) << vertices;
		auto model = loadModelFile(file);
		ASSERT_TRUE(model.ok()) << model.error().message;
		EXPECT_EQ((*model)->mesh().faces, mesh_.faces) << vertices;
	}
}

TEST_F(ForestFileTest, ViewPointsIntoTheMapping)
{
	const fs::path file = save(TemplateEncoding::kFloat32);
	auto model = loadModelFile(file);
	ASSERT_TRUE(model.ok()) << model.error().message;
	const auto *mapped = dynamic_cast<const MappedObjectModel *>(model->get());
	ASSERT_NE(mapped, nullptr);
	const auto range = mapped->mapping();
	EXPECT_EQ(range.size(), fs::file_size(file));
	// The mapping is the file's bytes.
	const Bytes b = test::readBytes(file);
	EXPECT_EQ(std::memcmp(range.data(), b.data(), b.size()), 0);
	for (const TreeView &tv : mapped->forest().trees) {
		EXPECT_TRUE(inside(tv.templates, range));
		EXPECT_TRUE(inside(tv.nodes.data(), range));
		EXPECT_TRUE(inside(tv.votes.data(), range));
	}
	EXPECT_TRUE(inside(mapped->forest().rotations.data(), range));
}

TEST_F(ForestFileTest, SummaryCountsMatchTheForest)
{
	const fs::path file = save(TemplateEncoding::kUint8);
	auto s = summariseModelFile(file);
	ASSERT_TRUE(s.ok()) << s.error().message;
	EXPECT_EQ(s->version, 2u);
	EXPECT_EQ(s->fileSize, fs::file_size(file));
	EXPECT_EQ(s->dims, 96);
	EXPECT_EQ(s->encoding, TemplateEncoding::kUint8);
	ASSERT_EQ(s->trees.size(), forest_.trees.size());
	for (size_t t = 0; t < forest_.trees.size(); ++t) {
		const HoughTree &tree = forest_.trees[t];
		EXPECT_EQ(s->trees[t].nodes, tree.nodes.size());
		EXPECT_EQ(s->trees[t].leaves, tree.leafCount());
		EXPECT_EQ(s->trees[t].templates, tree.templates.size() / 96);
		EXPECT_EQ(s->trees[t].votes, tree.votes.size());
		EXPECT_EQ(s->trees[t].depth, tree.depth());
	}
	EXPECT_EQ(s->vertices, 8u);
	EXPECT_EQ(s->faces, 12u);
	EXPECT_TRUE(s->normals);
	const std::string text = formatForestFileSummary(*s);
	EXPECT_NE(text.find("NODES"), std::string::npos) << text;
	EXPECT_NE(text.find("bytes by part:"), std::string::npos) << text;
	// The parts add up to the file.
	uint64_t parts = 0;
	for (const char *name : {"mesh", "nodes", "templates", "votes", "params", "layout"}) {
		const size_t at = text.find(std::string("\n  ") + name + " ");
		ASSERT_NE(at, std::string::npos) << name << "\n" << text;
		parts += std::stoull(text.substr(at + 3 + std::strlen(name)));
	}
	EXPECT_EQ(parts, s->fileSize) << text;
	EXPECT_NE(text.find("\"obj_id\": 6"), std::string::npos) << text;
}

// A chain of `depth` levels: split i (node 2i) has the leaf 2i+1 on the
// left and the next split (or the last leaf) 2i+2 on the right. With extra,
// an unreachable split with two leaves follows, for the forged test below.
HoughForest chainForest(int depth, bool extra)
{
	HoughForest f;
	f.dims = test::kFixtureDims;
	HoughTree t;
	const int splits = depth - 1;
	for (int i = 0; i < splits; ++i) {
		TreeNode n;
		n.left = 2 * i + 1;
		n.right = 2 * i + 2;
		n.templateIndex = static_cast<uint32_t>(i);
		n.threshold = 0.5f;
		t.nodes.push_back(n);
		t.nodes.push_back(TreeNode{});
	}
	t.nodes.push_back(TreeNode{});
	int templates = splits;
	if (extra) {
		TreeNode n;
		n.left = static_cast<int32_t>(t.nodes.size()) + 1;
		n.right = n.left + 1;
		n.templateIndex = static_cast<uint32_t>(templates++);
		t.nodes.push_back(n);
		t.nodes.push_back(TreeNode{});
		t.nodes.push_back(TreeNode{});
	}
	t.templates.assign(size_t(templates) * test::kFixtureDims, 0.1f);
	f.trees.push_back(t);
	return f;
}

TEST_F(ForestFileTest, DepthLimit)
{
	forest_ = chainForest(64, false);
	ASSERT_EQ(forest_.trees[0].depth(), 64);
	auto model = loadModelFile(save(TemplateEncoding::kFloat32, "deep64.ihf"));
	ASSERT_TRUE(model.ok()) << model.error().message;
	EXPECT_EQ(dynamic_cast<const MappedObjectModel &>(**model).summary().trees[0].depth, 64);

	forest_ = chainForest(65, false);
	ForestStorage storage(forest_, TemplateEncoding::kFloat32);
	Status s = saveModelFile(dir_ / "deep65.ihf", params_, mesh_, storage.view());
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("deeper than 64"), std::string::npos) << s.error().message;
	EXPECT_FALSE(fs::exists(dir_ / "deep65.ihf"));

	// The loader: the last split of a 64-deep chain is rewired to the extra
	// split, making the chain 65 deep.
	forest_ = chainForest(64, true);
	Bytes b = test::readBytes(save(TemplateEncoding::kFloat32, "deep_forged.ihf"));
	const auto entries = test::rawEntries(b);
	const auto *nodes = test::findEntry(entries, test::kRawNodes, 0);
	ASSERT_TRUE(nodes);
	const size_t lastSplit = 2 * 62; // split 62, at depth 63
	test::wr32(b, nodes->offset + 32 * lastSplit + 4, 127); // right child
	test::resealCrcs(b);
	Error e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kCorrupt);
	EXPECT_NE(e.message.find("tree 0 node 127: tree deeper than 64"), std::string::npos)
		<< e.message;
}

TEST_F(ForestFileTest, TruncatedFilesAreRefused)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kUint8));
	for (size_t cut : {size_t{0}, size_t{10}, size_t{63}, size_t{64}, size_t{200}, full.size() / 2,
			   full.size() - 64, full.size() - 1}) {
		Error e = loadErrorOf(Bytes(full.begin(), full.begin() + cut));
		EXPECT_EQ(e.code, Errc::kCorrupt) << "cut at " << cut;
		EXPECT_NE(e.message.find("truncated"), std::string::npos)
			<< "cut at " << cut << ": " << e.message;
	}
	Bytes longer = full;
	longer.resize(full.size() + 64);
	Error e = loadErrorOf(longer);
	EXPECT_NE(e.message.find("trailing data"), std::string::npos) << e.message;
}

TEST_F(ForestFileTest, FlippedByteInEachSectionIsNamed)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kFloat32));
	const auto entries = test::rawEntries(full);
	const char *names[] = {"",	     "PARAMS",	   "FOREST",	"MESH_VERTICES",
			       "MESH_FACES", "MESH_NORMALS", "ROTATIONS"};
	int checked = 0;
	for (const auto &entry : entries) {
		if (entry.size == 0)
			continue;
		Bytes b = full;
		b[entry.offset + entry.size / 2] ^= 0x10;
		Error e = loadErrorOf(b);
		std::string want;
		if (entry.type <= test::kRawRotations)
			want = names[entry.type];
		else
			want = std::string(entry.type == test::kRawNodes ? "NODES"
					   : entry.type == test::kRawTemplates ? "TEMPLATES"
									       : "VOTES") +
			       " of tree " + std::to_string(entry.tree);
		EXPECT_EQ(e.code, Errc::kCorrupt);
		EXPECT_NE(e.message.find("(" + want + "): CRC mismatch"), std::string::npos)
			<< want << ": " << e.message;
		++checked;
	}
	EXPECT_GE(checked, 15);

	Bytes b = full;
	b[44] ^= 1; // reserved header byte, covered by the header CRC
	EXPECT_NE(loadErrorOf(b).message.find("header CRC mismatch"), std::string::npos);
	b = full;
	b[64 + 16] ^= 1; // size of the first section entry
	EXPECT_NE(loadErrorOf(b).message.find("section table CRC mismatch"), std::string::npos);
}

TEST_F(ForestFileTest, WrongMagicVersionAndByteOrder)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kFloat32));
	Bytes b = full;
	b[0] = 'X';
	Error e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kCorrupt);
	EXPECT_NE(e.message.find("not an ihf forest file"), std::string::npos) << e.message;

	b = full;
	test::wr32(b, 8, 1);
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kUnsupported);
	EXPECT_NE(e.message.find("forest file version 1; this ihf reads 2 to 3: retrain with ihf train"),
		  std::string::npos)
		<< e.message;

	b = full;
	test::wr32(b, 12, 0x04030201); // as a big-endian writer would leave it
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kUnsupported);
	EXPECT_NE(e.message.find("big-endian"), std::string::npos) << e.message;
}

// Rewrites one field of one node of tree 1 and reseals the CRCs.
Bytes forgeNode(const Bytes &full, uint32_t node, size_t field, uint32_t value)
{
	Bytes b = full;
	const auto entries = test::rawEntries(b);
	const auto *nodes = test::findEntry(entries, test::kRawNodes, 1);
	EXPECT_TRUE(nodes);
	test::wr32(b, nodes->offset + 32 * size_t{node} + field, value);
	test::resealCrcs(b);
	return b;
}

TEST_F(ForestFileTest, ForgedNodesAreRefused)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kFloat32));
	const HoughTree &tree = forest_.trees[1];
	// A split that is not the root, and a leaf with votes.
	uint32_t split = 0, leaf = 0;
	for (uint32_t i = 1; i < tree.nodes.size(); ++i)
		if (!tree.nodes[i].isLeaf() && split == 0)
			split = i;
	for (uint32_t i = 0; i < tree.nodes.size(); ++i)
		if (tree.nodes[i].isLeaf() && tree.nodes[i].voteCount > 0 && leaf == 0)
			leaf = i;
	ASSERT_GT(split, 0u);
	ASSERT_GT(leaf, 0u);
	const std::string at = "tree 1 node " + std::to_string(split) + ": ";

	// Left child pointing back at the root: a cycle.
	Error e = loadErrorOf(forgeNode(full, split, 0, 0));
	EXPECT_EQ(e.code, Errc::kCorrupt);
	EXPECT_NE(e.message.find(at + "child index 0 points backwards"), std::string::npos)
		<< e.message;
	// Pointing at itself.
	e = loadErrorOf(forgeNode(full, split, 4, split));
	EXPECT_NE(e.message.find(at + "child index " + std::to_string(split) + " points backwards"),
		  std::string::npos)
		<< e.message;
	// Past the end.
	const uint32_t n = static_cast<uint32_t>(tree.nodes.size());
	e = loadErrorOf(forgeNode(full, split, 4, n));
	EXPECT_NE(e.message.find(at + "child index " + std::to_string(n) + " out of range"),
		  std::string::npos)
		<< e.message;
	// Half a leaf.
	e = loadErrorOf(forgeNode(full, split, 0, 0xffffffffu));
	EXPECT_NE(e.message.find(at + "child index -1"), std::string::npos) << e.message;
	// Template that does not exist.
	const uint32_t templates = static_cast<uint32_t>(tree.templates.size() / 96);
	e = loadErrorOf(forgeNode(full, split, 8, templates));
	EXPECT_NE(e.message.find(at + "template index " + std::to_string(templates) +
				 " out of range"),
		  std::string::npos)
		<< e.message;

	// Leaf votes running past the tree's votes.
	const std::string leafAt = "tree 1 node " + std::to_string(leaf) + ": ";
	e = loadErrorOf(forgeNode(full, leaf, 24, static_cast<uint32_t>(tree.votes.size())));
	EXPECT_NE(e.message.find(leafAt + "leaf votes"), std::string::npos) << e.message;
	EXPECT_NE(e.message.find("outside the tree's " + std::to_string(tree.votes.size()) + " votes"),
		  std::string::npos)
		<< e.message;
	e = loadErrorOf(forgeNode(full, leaf, 28, 0xffffffffu)); // count overflowing 32 bits
	EXPECT_NE(e.message.find(leafAt + "leaf votes"), std::string::npos) << e.message;

	// The unforged bytes still load (the forging itself is sound).
	Bytes same = full;
	test::resealCrcs(same);
	fs::path okFile = dir_ / "resealed.ihf";
	test::writeBytes(okFile, same);
	EXPECT_TRUE(loadModelFile(okFile).ok());
}

TEST_F(ForestFileTest, ForgedTableAndParamsAreRefused)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kUint8));
	const auto entries = test::rawEntries(full);

	// A section moved off its 64-byte boundary.
	Bytes b = full;
	const auto *votes = test::findEntry(entries, test::kRawVotes, 2);
	test::wr32(b, votes->at + 8, static_cast<uint32_t>(votes->offset + 4));
	test::resealCrcs(b);
	Error e = loadErrorOf(b);
	EXPECT_NE(e.message.find("(VOTES of tree 2): offset"), std::string::npos) << e.message;

	// A section running past the end of the file.
	b = full;
	test::wr32(b, votes->at + 16, static_cast<uint32_t>(full.size()));
	test::wr32(b, votes->at + 28, static_cast<uint32_t>(full.size() / 16));
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("(VOTES of tree 2): bytes"), std::string::npos) << e.message;

	// Wrong element size for the encoding: claim float templates.
	b = full;
	const auto *forest = test::findEntry(entries, test::kRawForest);
	test::wr32(b, forest->offset + 4, 0); // encoding float32
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("TEMPLATE_OFFSETS of tree 0: float32 templates have no offsets"),
		  std::string::npos)
		<< e.message;

	// dims disagreeing with the parameters' HoCP settings.
	b = full;
	test::wr32(b, forest->offset + 0, 64);
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("FOREST: dims 64 do not match the HoCP dimension 96"),
		  std::string::npos)
		<< e.message;

	// A face index past the vertices.
	b = full;
	const auto *faces = test::findEntry(entries, test::kRawFaces);
	b[faces->offset + 6 * 5 + 4] = 8; // u16 faces: 8 vertices
	b[faces->offset + 6 * 5 + 5] = 0;
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("MESH_FACES: face 5 uses vertex 8 of 8"), std::string::npos)
		<< e.message;

	// PARAMS with a bad field: the error names the file, section and field.
	b = full;
	const auto *params = test::findEntry(entries, test::kRawParams);
	std::string text(b.begin() + params->offset, b.begin() + params->offset + params->size);
	const size_t pos = text.find("\"n_r\": 3");
	ASSERT_NE(pos, std::string::npos) << text;
	b[params->offset + pos + 7] = '0';
	test::resealCrcs(b);
	fs::path bad = dir_ / "params.ihf";
	test::writeBytes(bad, b);
	e = loadError(bad);
	EXPECT_NE(e.message.find(bad.string() + ": PARAMS: hocp.n_r: must be at least 1"),
		  std::string::npos)
		<< e.message;
}

// The sparse templates and the vote rotations are checked at load, so the
// walk may follow them unchecked.
TEST_F(ForestFileTest, ForgedTemplatesAndRotationsAreRefused)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kUint8));
	const auto entries = test::rawEntries(full);
	const auto *templ = test::findEntry(entries, test::kRawTemplates, 1);
	const auto *offsets = test::findEntry(entries, test::kRawTemplateOffsets, 1);
	const auto *votes = test::findEntry(entries, test::kRawVotes, 1);
	const auto *rotations = test::findEntry(entries, test::kRawRotations);
	ASSERT_TRUE(templ && offsets && votes && rotations);
	ASSERT_GE(offsets->elementCount, 2u);

	// A record that does not start where the previous one ends.
	Bytes b = full;
	test::wr32(b, offsets->offset + 4, test::rd32(b, offsets->offset + 4) + 1);
	test::resealCrcs(b);
	Error e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kCorrupt);
	EXPECT_NE(e.message.find("TEMPLATES of tree 1: template 1: record at byte"), std::string::npos)
		<< e.message;

	// One more bin present in the first record: its values now run into
	// the second record, which no longer starts at its offset.
	b = full;
	size_t clear = 0;
	while (clear < 96 && ((b[templ->offset + clear / 8] >> (clear % 8)) & 1))
		++clear;
	ASSERT_LT(clear, 96u);
	b[templ->offset + clear / 8] |= static_cast<uint8_t>(1u << (clear % 8));
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("TEMPLATES of tree 1: template 1: record at byte"), std::string::npos)
		<< e.message;

	// The last record's values running past the section.
	b = full;
	const uint32_t last = test::rd32(b, offsets->offset + 4 * (offsets->elementCount - 1));
	for (size_t i = 0; i < 12; ++i)
		b[templ->offset + last + i] = 0xff;
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("values run past the end of the templates"), std::string::npos)
		<< e.message;

	// A vote whose rotation is not in the table.
	b = full;
	b[votes->offset + 6] = static_cast<uint8_t>(rotations->elementCount & 0xff);
	b[votes->offset + 7] = static_cast<uint8_t>(rotations->elementCount >> 8);
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("VOTES of tree 1: vote 0: rotation " +
				 std::to_string(rotations->elementCount) + " out of range"),
		  std::string::npos)
		<< e.message;

	// A float32 file claiming uint8 templates has no offsets.
	b = test::readBytes(save(TemplateEncoding::kFloat32, "float.ihf"));
	const auto floatEntries = test::rawEntries(b);
	const auto *forest = test::findEntry(floatEntries, test::kRawForest);
	test::wr32(b, forest->offset + 4, 1);
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_NE(e.message.find("no TEMPLATE_OFFSETS section for tree 0"), std::string::npos)
		<< e.message;
}

// Counts that would make the loader allocate or compute beyond reason are
// refused first (inputs found by tests/fuzz/fuzz_forest_file): a tree count
// of 2^32 - 1 reserved ~170 GB; an n_phi whose bins product overflows int
// to the stored dims was accepted.
TEST_F(ForestFileTest, HugeCountsAreRefusedBeforeAllocating)
{
	const Bytes full = test::readBytes(save(TemplateEncoding::kUint8));
	const auto entries = test::rawEntries(full);

	Bytes b = full;
	const auto *forest = test::findEntry(entries, test::kRawForest);
	test::wr32(b, forest->offset + 8, 0xFFFFFFFFu);
	test::resealCrcs(b);
	Error e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kCorrupt);
	EXPECT_NE(e.message.find("FOREST: 4294967295 trees but the section table has"), std::string::npos)
		<< e.message;

	// 2 x 3 x 4 x (4 + 2^29) is 96 modulo 2^32. The PARAMS text keeps its
	// length: the longer number takes the place of indentation.
	b = full;
	const auto *params = test::findEntry(entries, test::kRawParams);
	std::string text(b.begin() + params->offset, b.begin() + params->offset + params->size);
	const std::string from = "\"n_phi\": 4", to = "\"n_phi\":536870916";
	const size_t pos = text.find(from);
	ASSERT_NE(pos, std::string::npos) << text;
	text.replace(pos, from.size(), to);
	// One space less of indentation on each of the first lines.
	for (size_t grow = to.size() - from.size(), at = 0; grow > 0; --grow) {
		at = text.find("\n ", at);
		ASSERT_NE(at, std::string::npos) << text;
		text.erase(++at, 1);
	}
	ASSERT_EQ(text.size(), params->size);
	std::copy(text.begin(), text.end(), b.begin() + params->offset);
	test::resealCrcs(b);
	e = loadErrorOf(b);
	EXPECT_EQ(e.code, Errc::kOutOfRange);
	EXPECT_NE(e.message.find("PARAMS: hocp: bin counts n_r 3 x n_theta 4 x n_phi 536870916 give 12884901984 "
				 "dimensions, more than the 65536 allowed"),
		  std::string::npos)
		<< e.message;

	// The writer refuses such parameters too.
	params_.hocp.nPhi = 536870916;
	ForestStorage storage(forest_, TemplateEncoding::kUint8);
	Status s = saveModelFile(dir_ / "wide.ihf", params_, mesh_, storage.view());
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("n_phi 536870916"), std::string::npos) << s.error().message;
}

TEST_F(ForestFileTest, MissingFile)
{
	Error e = loadError(dir_ / "nothing.ihf");
	EXPECT_EQ(e.code, Errc::kNotFound);
	EXPECT_NE(e.message.find("file not found"), std::string::npos) << e.message;

	Error d = loadError(dir_);
	EXPECT_EQ(d.code, Errc::kIo);
}

TEST_F(ForestFileTest, SaveIntoMissingFolderFailsCleanly)
{
	ForestStorage storage(forest_, TemplateEncoding::kUint8);
	const fs::path file = dir_ / "no_such_dir" / "model.ihf";
	Status s = saveModelFile(file, params_, mesh_, storage.view());
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find(file.string()), std::string::npos) << s.error().message;
	EXPECT_NE(s.error().message.find("does not exist"), std::string::npos) << s.error().message;
	EXPECT_FALSE(fs::exists(dir_ / "no_such_dir"));
	EXPECT_TRUE(fs::is_empty(dir_)); // no temporary file either
}

TEST_F(ForestFileTest, FailedSaveKeepsTheOldFile)
{
	const fs::path file = save(TemplateEncoding::kFloat32);
	const Bytes before = test::readBytes(file);

	// Descriptor settings that do not match the forest's dims.
	ModelParams other = params_;
	other.hocp.nR = 4;
	ForestStorage storage(forest_, TemplateEncoding::kUint8);
	Status s = saveModelFile(file, other, mesh_, storage.view());
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("forest dims 96 do not match the HoCP dimension 128"),
		  std::string::npos)
		<< s.error().message;

	// A broken tree in memory.
	HoughForest broken = forest_;
	broken.trees[2].nodes[0].right = 0;
	ForestStorage brokenStorage(broken, TemplateEncoding::kUint8);
	s = saveModelFile(file, params_, mesh_, brokenStorage.view());
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("tree 2 node 0: child index 0 points backwards"),
		  std::string::npos)
		<< s.error().message;

	EXPECT_EQ(test::readBytes(file), before);
	size_t files = 0;
	for ([[maybe_unused]] const auto &entry : fs::directory_iterator(dir_))
		++files;
	EXPECT_EQ(files, 1u);
}

TEST_F(ForestFileTest, OverwriteReplacesAtomically)
{
	const fs::path file = save(TemplateEncoding::kFloat32);
	// A model loaded from the old file keeps working after the new one is
	// renamed over it: the mapping holds the old inode.
	auto oldModel = loadModelFile(file);
	ASSERT_TRUE(oldModel.ok());
	forest_ = test::makeForest(2, 5, 7);
	save(TemplateEncoding::kUint8);
	auto newModel = loadModelFile(file);
	ASSERT_TRUE(newModel.ok()) << newModel.error().message;
	EXPECT_EQ((*newModel)->forest().trees.size(), 2u);
	EXPECT_EQ((*oldModel)->forest().trees.size(), 3u);
	EXPECT_EQ((*oldModel)->forest().encoding, TemplateEncoding::kFloat32);
	expectRoundTrip(forest_, TemplateEncoding::kUint8, **newModel, params_, mesh_);
}

} // namespace
} // namespace ihf

namespace ihf {
namespace {

NearSymmetry nearSymmetryFixture(float turnDeg, float share)
{
	NearSymmetry s;
	s.axis = Eigen::Vector3f(0.0f, 0.6f, 0.8f);
	s.point = Eigen::Vector3f(1.5f, -2.25f, 40.0f);
	s.turnDeg = turnDeg;
	s.differingShare = share;
	return s;
}

class NearSymmetryFileTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		dir_ = test::freshTempDir(std::string("model_sym_") +
					  ::testing::UnitTest::GetInstance()->current_test_info()->name());
		params_ = test::makeParams();
		mesh_ = test::makeMesh();
		forest_ = test::makeForest(2, 5, 7);
	}
	Status save(const fs::path &file, std::span<const NearSymmetry> symmetries)
	{
		ForestStorage storage(forest_, TemplateEncoding::kUint8);
		return saveModelFile(file, params_, mesh_, storage.view(), symmetries);
	}

	fs::path dir_;
	ModelParams params_;
	Mesh mesh_;
	HoughForest forest_;
};

// Stored as version 3 with a NEAR_SYMMETRIES section of 32-byte records,
// read back exactly and shown by the summary.
TEST_F(NearSymmetryFileTest, RoundTripAsVersion3)
{
	const NearSymmetry stored[] = {nearSymmetryFixture(0.0f, 0.08f), nearSymmetryFixture(180.0f, 0.21f)};
	const fs::path file = dir_ / "sym.ihf";
	ASSERT_TRUE(save(file, stored).ok());
	const test::Bytes b = test::readBytes(file);
	EXPECT_EQ(test::rd32(b, 8), 3u);
	const auto entries = test::rawEntries(b);
	const auto *sec = test::findEntry(entries, 7, 0);
	ASSERT_TRUE(sec);
	EXPECT_EQ(sec->elementSize, 32u);
	EXPECT_EQ(sec->elementCount, 2u);

	auto model = loadModelFile(file);
	ASSERT_TRUE(model.ok()) << model.error().message;
	const auto got = (*model)->nearSymmetries();
	ASSERT_EQ(got.size(), 2u);
	for (size_t i = 0; i < 2; ++i) {
		EXPECT_EQ(got[i].axis, stored[i].axis);
		EXPECT_EQ(got[i].point, stored[i].point);
		EXPECT_EQ(got[i].turnDeg, stored[i].turnDeg);
		EXPECT_EQ(got[i].differingShare, stored[i].differingShare);
	}
	auto summary = summariseModelFile(file);
	ASSERT_TRUE(summary.ok());
	const std::string text = formatForestFileSummary(*summary);
	EXPECT_NE(text.find("near-symmetries: 2"), std::string::npos) << text;
	EXPECT_NE(text.find("any turn, differing 8.0 %"), std::string::npos) << text;
	EXPECT_NE(text.find("turn 180 deg, differing 21.0 %"), std::string::npos) << text;
}

// Without near-symmetries the file stays version 2 (older readers read it)
// and loads with none.
TEST_F(NearSymmetryFileTest, NoneStoredIsVersion2)
{
	const fs::path file = dir_ / "plain.ihf";
	ASSERT_TRUE(save(file, {}).ok());
	EXPECT_EQ(test::rd32(test::readBytes(file), 8), 2u);
	auto model = loadModelFile(file);
	ASSERT_TRUE(model.ok()) << model.error().message;
	EXPECT_TRUE((*model)->nearSymmetries().empty());
	auto summary = summariseModelFile(file);
	ASSERT_TRUE(summary.ok());
	EXPECT_NE(formatForestFileSummary(*summary).find("near-symmetries: none stored"), std::string::npos);
}

TEST_F(NearSymmetryFileTest, BadRecordsAreRefused)
{
	NearSymmetry bad = nearSymmetryFixture(90.0f, 0.1f);
	bad.axis *= 2.0f;
	Status s = save(dir_ / "bad.ihf", std::span<const NearSymmetry>(&bad, 1));
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("axis of length"), std::string::npos) << s.error().message;

	// A stored record forged: the share out of range, the CRCs resealed.
	const NearSymmetry good = nearSymmetryFixture(90.0f, 0.1f);
	const fs::path file = dir_ / "forged.ihf";
	ASSERT_TRUE(save(file, std::span<const NearSymmetry>(&good, 1)).ok());
	test::Bytes b = test::readBytes(file);
	const auto forgedEntries = test::rawEntries(b);
	const auto *sec = test::findEntry(forgedEntries, 7, 0);
	ASSERT_TRUE(sec);
	const float share = 1.5f;
	uint32_t bits;
	std::memcpy(&bits, &share, 4);
	test::wr32(b, sec->offset + 28, bits);
	test::resealCrcs(b);
	test::writeBytes(file, b);
	auto r = loadModelFile(file);
	ASSERT_FALSE(r.ok());
	EXPECT_NE(r.error().message.find("NEAR_SYMMETRIES: record 0: differing share"), std::string::npos)
		<< r.error().message;

	// The section in a file that says version 2.
	b = test::readBytes(file);
	test::wr32(b, 8, 2);
	test::resealCrcs(b);
	test::writeBytes(file, b);
	r = loadModelFile(file);
	ASSERT_FALSE(r.ok());
	EXPECT_NE(r.error().message.find("NEAR_SYMMETRIES in a version 2 file"), std::string::npos)
		<< r.error().message;
}

} // namespace
} // namespace ihf
