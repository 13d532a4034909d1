// SPDX-License-Identifier: MIT
// Byte-order portability of the forest file: tests/data/forest_amd64.ihf was
// written on amd64 from the shared fixture (makeForest(2, 5, 7), float32
// templates). On every target (aarch64 and armhf under qemu included) it must
// load, and the in-place views must equal the fixture rebuilt on the target;
// the target's own writer must produce the same bytes.
//
// Regenerate (amd64 only, when the format version changes):
//   IHF_WRITE_GOLDEN=1 build/bin/test_model --gtest_filter='ForestGolden.*'

#include <cstdlib>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "core/forest/forest_view.h"
#include "core/model/forest_file.h"
#include "tests/common/test_paths.h"
#include "tests/model/model_fixture.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

fs::path goldenFile()
{
	return test::sourceDir() / "tests" / "data" / "forest_amd64.ihf";
}

class ForestGolden : public ::testing::Test
{
protected:
	void SetUp() override
	{
		params_ = test::makeParams();
		mesh_ = test::makeMesh();
		forest_ = test::makeForest(2, 5, 7);
		storage_ = ForestStorage(forest_, TemplateEncoding::kFloat32);
		if (std::getenv("IHF_WRITE_GOLDEN")) {
			Status s = saveModelFile(goldenFile(), params_, mesh_, storage_.view());
			ASSERT_TRUE(s.ok()) << s.error().message;
		}
	}

	ModelParams params_;
	Mesh mesh_;
	HoughForest forest_;
	ForestStorage storage_;
};

TEST_F(ForestGolden, Amd64FileLoadsWithIdenticalContent)
{
	auto model = loadModelFile(goldenFile());
	ASSERT_TRUE(model.ok()) << model.error().message;
	test::expectParamsEqual(params_, (*model)->params());

	const Mesh &m = (*model)->mesh();
	ASSERT_EQ(m.vertices.size(), mesh_.vertices.size());
	ASSERT_EQ(m.normals.size(), mesh_.normals.size());
	ASSERT_EQ(m.faces.size(), mesh_.faces.size());
	for (size_t i = 0; i < mesh_.vertices.size(); ++i) {
		EXPECT_EQ(m.vertices[i], mesh_.vertices[i]) << "vertex " << i;
		EXPECT_EQ(m.normals[i], mesh_.normals[i]) << "normal " << i;
	}
	for (size_t i = 0; i < mesh_.faces.size(); ++i)
		EXPECT_EQ(m.faces[i], mesh_.faces[i]) << "face " << i;
	// Spot values known without the fixture: the cube's first corner.
	EXPECT_EQ(m.vertices[0].x(), -40.0f);
	EXPECT_EQ(m.vertices[7].y(), 30.5f);
	EXPECT_EQ(m.vertices[7].z(), 20.25f);

	const ForestView &got = (*model)->forest();
	const ForestView &want = storage_.view();
	EXPECT_EQ(got.dims, test::kFixtureDims);
	EXPECT_EQ(got.encoding, TemplateEncoding::kFloat32);
	ASSERT_EQ(got.trees.size(), 2u);
	for (size_t t = 0; t < want.trees.size(); ++t) {
		const TreeView &g = got.trees[t];
		const TreeView &w = want.trees[t];
		ASSERT_EQ(g.nodes.size(), w.nodes.size()) << "tree " << t;
		ASSERT_EQ(g.votes.size(), w.votes.size()) << "tree " << t;
		// Field by field, so a byte-order or padding fault names the field.
		for (size_t i = 0; i < w.nodes.size(); ++i) {
			const TreeNode &a = g.nodes[i];
			const TreeNode &b = w.nodes[i];
			EXPECT_EQ(a.left, b.left) << "tree " << t << " node " << i;
			EXPECT_EQ(a.right, b.right) << "tree " << t << " node " << i;
			EXPECT_EQ(a.templateIndex, b.templateIndex) << "tree " << t << " node " << i;
			EXPECT_EQ(a.threshold, b.threshold) << "tree " << t << " node " << i;
			EXPECT_EQ(a.zMin, b.zMin) << "tree " << t << " node " << i;
			EXPECT_EQ(a.zMax, b.zMax) << "tree " << t << " node " << i;
			EXPECT_EQ(a.voteBegin, b.voteBegin) << "tree " << t << " node " << i;
			EXPECT_EQ(a.voteCount, b.voteCount) << "tree " << t << " node " << i;
		}
		const size_t templates = forest_.trees[t].templates.size();
		const auto *gf = static_cast<const float *>(g.templates);
		const auto *wf = static_cast<const float *>(w.templates);
		size_t badBins = 0;
		for (size_t i = 0; i < templates; ++i)
			badBins += gf[i] != wf[i];
		EXPECT_EQ(badBins, 0u) << "tree " << t;
		for (size_t i = 0; i < w.votes.size(); ++i) {
			for (int k = 0; k < 3; ++k)
				EXPECT_EQ(g.votes[i].offset[k], w.votes[i].offset[k]) << "vote " << i;
			EXPECT_EQ(g.votes[i].rotation, w.votes[i].rotation) << "vote " << i;
		}
	}
	ASSERT_EQ(got.rotations.size(), want.rotations.size());
	for (size_t i = 0; i < want.rotations.size(); ++i)
		for (int k = 0; k < 4; ++k)
			EXPECT_EQ(got.rotations[i].q[k], want.rotations[i].q[k]) << "rotation " << i;
}

TEST_F(ForestGolden, TargetWriterProducesTheSameBytes)
{
	const fs::path dir = test::freshTempDir("model_golden_write");
	const fs::path file = dir / "target.ihf";
	Status s = saveModelFile(file, params_, mesh_, storage_.view());
	ASSERT_TRUE(s.ok()) << s.error().message;
	const test::Bytes mine = test::readBytes(file);
	const test::Bytes golden = test::readBytes(goldenFile());
	ASSERT_EQ(mine.size(), golden.size());
	size_t firstDiff = mine.size();
	for (size_t i = 0; i < mine.size() && firstDiff == mine.size(); ++i)
		if (mine[i] != golden[i])
			firstDiff = i;
	EXPECT_EQ(firstDiff, mine.size()) << "first differing byte at offset " << firstDiff;
}

} // namespace
} // namespace ihf
