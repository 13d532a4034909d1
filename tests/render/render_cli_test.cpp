// SPDX-License-Identifier: MIT
// `ihf render` end to end: the PNG it writes equals a direct render rounded
// to millimetres, and bad input fails with the documented exit codes and
// leaves no output behind.

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/dataset/bop_io.h"
#include "core/geometry/ply_loader.h"
#include "core/render/depth_renderer.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

// obj 5 (can) in LM-O test/000002 image 3.
const char *kCanR = "0.94893088,0.30725587,-0.07208124,0.24200515,-0.85502122,-0.45872652,"
		    "-0.20257109,0.41784038,-0.88568011";
const char *kCanT = "134.36598053,45.77287271,964.78389285";

const auto q = test::quoted; // a path in single quotes, for the shell

std::string canArgs(const fs::path &model, const fs::path &out)
{
	return "render --model " + q(model) + " --camera " + q(test::lmoDir() / "camera.json") + " --R " + kCanR +
	       " --t " + kCanT + " --out " + q(out);
}

const fs::path kCan = test::lmoDir() / "models" / "obj_000005.ply";

TEST(RenderCli, HelpExitsZero)
{
	auto r = test::runIhf("render --help");
	EXPECT_EQ(r.exitCode, 0);
	EXPECT_NE(r.output.find("--model"), std::string::npos);
	EXPECT_NE(r.output.find("--preview"), std::string::npos);
}

TEST(RenderCli, WritesDepthEqualToDirectRender)
{
	const fs::path dir = test::freshTempDir("render_cli_ok");
	const fs::path out = dir / "depth.png", preview = dir / "preview.png";
	auto r = test::runIhf(canArgs(kCan, out) + " --preview " + q(preview));
	ASSERT_EQ(r.exitCode, 0) << r.output;

	auto png = readDepthPng(out);
	ASSERT_TRUE(png.ok()) << png.error().message;
	ASSERT_EQ(png->width(), 640);
	ASSERT_EQ(png->height(), 480);

	auto camera = readBopCamera(test::lmoDir() / "camera.json");
	ASSERT_TRUE(camera.ok());
	auto mesh = loadPly(kCan);
	ASSERT_TRUE(mesh.ok());
	Pose pose;
	pose.R << 0.94893088, 0.30725587, -0.07208124, 0.24200515, -0.85502122, -0.45872652, -0.20257109, 0.41784038,
		-0.88568011;
	pose.t = {134.36598053, 45.77287271, 964.78389285};
	DepthRenderer renderer(mesh->vertices.size());
	DepthImageMm depth(640, 480);
	ASSERT_TRUE(renderer.render(*mesh, pose, camera->intrinsics, depth.view()).ok());

	int covered = 0;
	for (int y = 0; y < 480; ++y) {
		for (int x = 0; x < 640; ++x) {
			const float z = depth.at(x, y);
			ASSERT_EQ(png->at(x, y), z > 0 ? static_cast<uint16_t>(std::lround(z)) : 0) << x << "," << y;
			covered += z > 0;
		}
	}
	EXPECT_NEAR(covered, 4330, 50); // px_count_all in scene_gt_info.json

	// The preview is an 8-bit RGB PNG of the same size (IHDR at byte 16).
	std::ifstream in(preview, std::ios::binary);
	unsigned char head[26] = {};
	in.read(reinterpret_cast<char *>(head), sizeof(head));
	ASSERT_TRUE(in.good());
	EXPECT_EQ(std::string(reinterpret_cast<char *>(head + 1), 3), "PNG");
	EXPECT_EQ((head[16] << 24) | (head[17] << 16) | (head[18] << 8) | head[19], 640);
	EXPECT_EQ((head[20] << 24) | (head[21] << 16) | (head[22] << 8) | head[23], 480);
	EXPECT_EQ(head[24], 8); // bit depth
	EXPECT_EQ(head[25], 2); // RGB
}

TEST(RenderCli, UsageErrorsExitTwo)
{
	const fs::path dir = test::freshTempDir("render_cli_usage");
	const fs::path out = dir / "depth.png";
	const std::string cam = " --camera " + q(test::lmoDir() / "camera.json");
	const std::string model = " --model " + q(kCan);
	for (const std::string &args : {
		     "render" + model + cam + " --R 1,0,0,0,1,0,0,0 --t 0,0,500 --out " + q(out), // 8 values
		     "render" + model + cam + " --R 1,0,0,0,1,0,0,0,1 --out " + q(out), // no --t
		     "render" + model + cam + " --R 2,0,0,0,1,0,0,0,1 --t 0,0,500 --out " + q(out), // not a rotation
		     "render" + model + cam + " --R 1,0,0,0,1,0,0,0,-1 --t 0,0,500 --out " + q(out), // reflection
		     "render --model " + q(dir / "nope.ply") + cam + " --R 1,0,0,0,1,0,0,0,1 --t 0,0,500 --out " + q(out),
	     }) {
		SCOPED_TRACE(args);
		auto r = test::runIhf(args);
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_FALSE(fs::exists(out));
	}
}

TEST(RenderCli, RuntimeErrorsExitOneAndWriteNothing)
{
	const fs::path dir = test::freshTempDir("render_cli_fail");
	const fs::path out = dir / "depth.png";

	// A model cut in half.
	std::ifstream in(kCan, std::ios::binary);
	std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
	const fs::path cut = dir / "cut.ply";
	std::ofstream(cut, std::ios::binary) << text.substr(0, text.size() / 2);
	auto r = test::runIhf(canArgs(cut, out));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find(cut.string()), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(out));

	// Output "folder" that is a file.
	const fs::path blocker = dir / "blocker";
	std::ofstream(blocker) << "x";
	const fs::path nowhere = blocker / "depth.png";
	r = test::runIhf(canArgs(kCan, nowhere));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find(nowhere.string()), std::string::npos) << r.output;

	// A broken camera file.
	const fs::path cam = dir / "camera.json";
	std::ofstream(cam) << "{\"fx\": 572.4}";
	r = test::runIhf("render --model " + q(kCan) + " --camera " + q(cam) + " --R " + kCanR + " --t " + kCanT +
			 " --out " + q(out));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find(cam.string()), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(out));
	// Nothing else left in the folder (no temporaries).
	int files = 0;
	for (const auto &e : fs::directory_iterator(dir))
		files += e.is_regular_file();
	EXPECT_EQ(files, 3); // cut.ply, blocker and camera.json
}

} // namespace
} // namespace ihf
