// SPDX-License-Identifier: MIT
// `ihf train` and `ihf render` on meshes as users have them: the bundled
// bunny as a binary STL trains the same trees as its PLY, the LM-O can as
// a GLB renders the same depth PNG as its PLY, and a format the build does
// not read fails with exit 1 and the file named.

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/mesh_import.h"
#include "core/geometry/ply_loader.h"
#include "tests/common/mesh_files.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

const auto q = test::quoted; // a path in single quotes, for the shell

std::string readBytes(const fs::path &path)
{
	std::ifstream in(path, std::ios::binary);
	std::ostringstream s;
	s << in.rdbuf();
	return s.str();
}

// What `ihf forest info` says of the trees: each NODES, TEMPLATES and
// VOTES section's tree, bytes, element size, count and CRC (not its offset,
// which moves with the sections before it), and the rows of the tree table.
// The parameters (mesh name, training time) and the stored mesh (vertex
// numbering, normals) may differ between a PLY and an STL of one surface.
std::string treeLines(const std::string &info)
{
	std::istringstream in(info);
	std::string line, out;
	while (std::getline(in, line)) {
		std::istringstream w(line);
		std::vector<std::string> words;
		for (std::string word; w >> word;)
			words.push_back(word);
		if (words.empty())
			continue;
		const std::string &type = words[0];
		if ((type == "NODES" || type == "TEMPLATES" || type == "VOTES") && words.size() == 7)
			words.erase(words.begin() + 2); // the offset
		else if (!(words.size() == 6 && (std::isdigit(static_cast<unsigned char>(type[0])) || type == "all")))
			continue;
		for (const auto &word : words)
			out += word + " ";
		out += "\n";
	}
	return out;
}

class MeshCliTest : public ::testing::Test
{
protected:
	void SetUp() override { dir_ = test::freshTempDir("mesh_cli"); }
	void TearDown() override { fs::remove_all(dir_); }
	fs::path dir_;
};

TEST_F(MeshCliTest, StlTrainsTheSameTreesAsItsPly)
{
	if (!meshImportHasAssimp())
		GTEST_SKIP() << "built without assimp";
	const fs::path ply = test::sourceDir() / "config" / "models" / "obj_000020.ply";
	auto mesh = loadPly(ply);
	ASSERT_TRUE(mesh.ok()) << mesh.error().message;
	const fs::path stl = dir_ / "obj_000020.stl";
	test::writeBytes(stl, test::stlBinary(*mesh));
	std::ofstream(dir_ / "train.toml") << "[views]\nviewpoints = 20\ninplane_steps = 2\n"
					      "[scales]\nfactors = [1.0]\nparts_per_image = 8\noccluded_views = 0.0\n"
					      "[parts]\nkind = \"variable\"\nmax_control_points = 256\n";

	const std::string common = " --config " + q(dir_ / "train.toml") + " --threads 2 --seed 3";
	auto a = test::runIhf("train --model " + q(ply) + common + " --out " + q(dir_ / "ply.ihf"));
	ASSERT_EQ(a.exitCode, 0) << a.output;
	auto b = test::runIhf("train --model " + q(stl) + common + " --out " + q(dir_ / "stl.ihf"));
	ASSERT_EQ(b.exitCode, 0) << b.output;
	EXPECT_NE(b.output.find("object 20"), std::string::npos) << "object id from obj_000020.stl: " << b.output;

	auto infoA = test::runIhf("forest info " + q(dir_ / "ply.ihf"));
	auto infoB = test::runIhf("forest info " + q(dir_ / "stl.ihf"));
	ASSERT_EQ(infoA.exitCode, 0) << infoA.output;
	ASSERT_EQ(infoB.exitCode, 0) << infoB.output;
	const std::string treesA = treeLines(infoA.output), treesB = treeLines(infoB.output);
	EXPECT_NE(treesA.find("NODES"), std::string::npos) << infoA.output;
	EXPECT_EQ(treesA, treesB);
	EXPECT_NE(infoB.output.find("\"mesh_name\": \"obj_000020.stl\""), std::string::npos) << infoB.output;
}

// obj 5 (can) in LM-O test/000002 image 3.
const char *kCanPose = " --R 0.94893088,0.30725587,-0.07208124,0.24200515,-0.85502122,-0.45872652,"
		       "-0.20257109,0.41784038,-0.88568011 --t 134.36598053,45.77287271,964.78389285";

TEST_F(MeshCliTest, GlbRendersTheSameDepthPngAsItsPly)
{
	if (!meshImportHasAssimp())
		GTEST_SKIP() << "built without assimp";
	const fs::path ply = test::lmoDir() / "models" / "obj_000005.ply";
	auto mesh = loadPly(ply);
	ASSERT_TRUE(mesh.ok()) << mesh.error().message;
	test::writeBytes(dir_ / "can.glb", test::glb(*mesh));
	const std::string camera = " --camera " + q(test::lmoDir() / "camera.json") + kCanPose;
	auto a = test::runIhf("render --model " + q(ply) + camera + " --out " + q(dir_ / "ply.png"));
	ASSERT_EQ(a.exitCode, 0) << a.output;
	auto b = test::runIhf("render --model " + q(dir_ / "can.glb") + camera + " --out " + q(dir_ / "glb.png"));
	ASSERT_EQ(b.exitCode, 0) << b.output;
	const std::string pa = readBytes(dir_ / "ply.png"), pb = readBytes(dir_ / "glb.png");
	EXPECT_GT(pa.size(), 100u);
	EXPECT_TRUE(pa == pb) << "the depth PNGs differ";
}

TEST_F(MeshCliTest, UnreadableFormatFailsNamingTheFile)
{
	test::writeBytes(dir_ / "obj_000001.fbx", "Kaydara FBX Binary");
	auto r = test::runIhf("train --model " + q(dir_ / "obj_000001.fbx") + " --out " + q(dir_ / "x.ihf"));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find((dir_ / "obj_000001.fbx").string() + ": unknown mesh format '.fbx'"), std::string::npos)
		<< r.output;
	EXPECT_FALSE(fs::exists(dir_ / "x.ihf"));

	// A 2 mm STL: read (with a warning about units) when the build has
	// assimp; otherwise exit 1 with the missing package named.
	test::writeBytes(dir_ / "obj_000001.stl", test::stlAscii(Mesh{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, {}, {{0, 1, 2}}}));
	std::ofstream(dir_ / "train.toml") << "[views]\nviewpoints = 4\ninplane_steps = 1\n[scales]\noccluded_views = 0.0\n"
					      "[parts]\nkind = \"variable\"\nmax_control_points = 256\n";
	r = test::runIhf("train --model " + q(dir_ / "obj_000001.stl") + " --config " + q(dir_ / "train.toml") +
			 " --out " + q(dir_ / "x.ihf"));
	if (meshImportHasAssimp()) {
		EXPECT_NE(r.output.find("is 2.83 mm across; coordinates are read as millimetres"), std::string::npos)
			<< r.output;
	} else {
		EXPECT_EQ(r.exitCode, 1) << r.output;
		EXPECT_NE(r.output.find("built without assimp: STL/OBJ/glTF need libassimp-dev"), std::string::npos)
			<< r.output;
	}
}

} // namespace
} // namespace ihf
