// SPDX-License-Identifier: MIT
// `ihf forest info` end to end: the summary of a saved file (counts checked
// against the forest it was built from), exit 1 naming the fault on a
// damaged file, exit 2 on usage errors.

#include <string>

#include <gtest/gtest.h>

#include "core/forest/forest_view.h"
#include "core/model/forest_file.h"
#include "tests/common/test_paths.h"
#include "tests/model/model_fixture.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

const auto q = test::quoted; // a path in single quotes, for the shell

class ForestCliTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		dir_ = test::freshTempDir("forest_cli");
		forest_ = test::makeForest(4, 6, 99);
		ForestStorage storage(forest_, TemplateEncoding::kUint8);
		file_ = dir_ / "obj_000006.ihf";
		Status s = saveModelFile(file_, test::makeParams(), test::makeMesh(), storage.view());
		ASSERT_TRUE(s.ok()) << s.error().message;
	}

	fs::path dir_;
	fs::path file_;
	HoughForest forest_;
};

TEST_F(ForestCliTest, InfoPrintsTheSummary)
{
	auto r = test::runIhf("forest info " + q(file_));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const std::string &out = r.output;
	EXPECT_NE(out.find("format version 2, " + std::to_string(fs::file_size(file_)) + " bytes"),
		  std::string::npos)
		<< out;
	EXPECT_NE(out.find("forest: 4 trees, dims 96, templates uint8"), std::string::npos) << out;
	EXPECT_NE(out.find("mesh: 8 vertices, 12 faces, with normals"), std::string::npos) << out;
	EXPECT_NE(out.find("\"weighting\": \"sign_split\""), std::string::npos) << out;
	for (const char *section : {"PARAMS", "FOREST", "MESH_VERTICES", "MESH_FACES",
				    "MESH_NORMALS", "ROTATIONS", "NODES", "TEMPLATES", "TEMPLATE_OFFSETS",
				    "VOTES", "bytes by part:"})
		EXPECT_NE(out.find(section), std::string::npos) << section;

	// Per-tree row: index, nodes, leaves, templates, votes, depth (then the
	// stored template bins).
	size_t nodes = 0;
	for (size_t t = 0; t < forest_.trees.size(); ++t) {
		const HoughTree &tree = forest_.trees[t];
		char row[128];
		std::snprintf(row, sizeof(row), "  %4zu %10zu %10zu %10zu %10zu %6d ", t,
			      tree.nodes.size(), tree.leafCount(), tree.templates.size() / 96,
			      tree.votes.size(), tree.depth());
		EXPECT_NE(out.find(row), std::string::npos) << "missing row: " << row << out;
		nodes += tree.nodes.size();
	}
	EXPECT_NE(out.find(" all " + std::string(10 - std::to_string(nodes).size(), ' ') +
			   std::to_string(nodes)),
		  std::string::npos)
		<< out;

	// The CRC column shows the stored checksums.
	const auto entries = test::rawEntries(test::readBytes(file_));
	char crc[16];
	std::snprintf(crc, sizeof(crc), "0x%08x", entries[0].crc);
	EXPECT_NE(out.find(crc), std::string::npos) << out;
}

TEST_F(ForestCliTest, CorruptFileExitsOne)
{
	test::Bytes b = test::readBytes(file_);
	const auto entries = test::rawEntries(b);
	const auto *votes = test::findEntry(entries, test::kRawVotes, 3);
	ASSERT_TRUE(votes && votes->size > 0);
	b[votes->offset + 3] ^= 0xff;
	const fs::path bad = dir_ / "bad.ihf";
	test::writeBytes(bad, b);
	auto r = test::runIhf("forest info " + q(bad));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("ihf forest info: " + bad.string()), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("(VOTES of tree 3): CRC mismatch"), std::string::npos) << r.output;

	// A file of the previous format version: refused, saying what to do.
	b = test::readBytes(file_);
	test::wr32(b, 8, 1);
	test::resealCrcs(b);
	const fs::path old = dir_ / "v1.ihf";
	test::writeBytes(old, b);
	r = test::runIhf("forest info " + q(old));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("forest file version 1; this ihf reads 2 to 3: retrain with ihf train"),
		  std::string::npos)
		<< r.output;

	r = test::runIhf("forest info " + q(dir_ / "missing.ihf"));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("missing.ihf: file not found"), std::string::npos) << r.output;
}

// A forest trained without near-symmetries gains them: the fixture's mesh
// is a box, which every half-turn about its axes maps onto itself.
TEST_F(ForestCliTest, SymmetriesAddsTheNearSymmetriesOfTheMesh)
{
	const fs::path out = dir_ / "with_symmetries.ihf";
	auto r = test::runIhf("forest symmetries " + q(file_) + " --out " + q(out));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	auto info = test::runIhf("forest info " + q(out));
	ASSERT_EQ(info.exitCode, 0) << info.output;
	EXPECT_NE(info.output.find("format version 3"), std::string::npos) << info.output;
	EXPECT_NE(info.output.find("NEAR_SYMMETRIES"), std::string::npos) << info.output;
	EXPECT_NE(info.output.find("turn 180 deg, differing 0."), std::string::npos) << info.output; // under 1 %
	// The rest of the forest is the input's.
	auto before = test::runIhf("forest info " + q(file_));
	EXPECT_NE(before.output.find("near-symmetries: none stored"), std::string::npos) << before.output;
	EXPECT_EQ(test::runIhf("forest symmetries " + q(dir_ / "missing.ihf") + " --out " + q(out)).exitCode, 1);
}

TEST_F(ForestCliTest, UsageErrorsExitTwo)
{
	EXPECT_EQ(test::runIhf("forest").exitCode, 2);
	EXPECT_EQ(test::runIhf("forest info").exitCode, 2);
	EXPECT_EQ(test::runIhf("forest info " + q(file_) + " extra").exitCode, 2);
	EXPECT_EQ(test::runIhf("forest frobnicate " + q(file_)).exitCode, 2);
	auto help = test::runIhf("forest info --help");
	EXPECT_EQ(help.exitCode, 0);
	EXPECT_NE(help.output.find("forest file (.ihf)"), std::string::npos) << help.output;
}

} // namespace
} // namespace ihf
