// SPDX-License-Identifier: MIT
// The simplified render mesh (mesh_simplify.h): on the LM-O can and ape it
// keeps a fraction of the faces, and a render of it at 1 m matches the full
// mesh's render to well within the score's 10 mm inlier band; it is closed
// (once oriented), and without its back faces it renders the same; bad input
// is refused with a reason.

#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/mesh_simplify.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/pose.h"
#include "core/render/depth_renderer.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

struct Agreement {
	double iou = 0;        // silhouettes
	double meanAbsMm = 0;  // depth where both render
	double p99AbsMm = 0;
};

// b rendered without its back faces when cullB.
Agreement compareRenders(const Mesh &a, const Mesh &b, const Pose &pose, bool cullB = false)
{
	const CameraIntrinsics K{572.4114, 573.57043, 160.0, 120.0, 320, 240};
	std::vector<float> da(static_cast<size_t>(K.width) * K.height, 0.0f), db(da.size(), 0.0f);
	DepthRenderer r(std::max(a.vertices.size(), b.vertices.size()));
	EXPECT_TRUE(r.render(a, pose, K, ImageView<float>(da.data(), K.width, K.height, K.width)));
	r.setCullBackFaces(cullB);
	EXPECT_TRUE(r.render(b, pose, K, ImageView<float>(db.data(), K.width, K.height, K.width)));
	int both = 0, either = 0;
	std::vector<double> diffs;
	for (size_t i = 0; i < da.size(); ++i) {
		const bool ia = da[i] > 0, ib = db[i] > 0;
		both += ia && ib;
		either += ia || ib;
		if (ia && ib)
			diffs.push_back(std::abs(static_cast<double>(da[i]) - db[i]));
	}
	Agreement g;
	g.iou = either ? static_cast<double>(both) / either : 0;
	if (!diffs.empty()) {
		double sum = 0;
		for (double d : diffs)
			sum += d;
		g.meanAbsMm = sum / diffs.size();
		std::sort(diffs.begin(), diffs.end());
		g.p99AbsMm = diffs[diffs.size() * 99 / 100];
	}
	return g;
}

constexpr float kErrorMm = 0.5f;

class RenderMesh : public ::testing::TestWithParam<const char *>
{
};

TEST_P(RenderMesh, FewerFacesTheSameRenderWithinTheBound)
{
	auto mesh = loadPly(test::lmoDir() / "models" / GetParam());
	ASSERT_TRUE(mesh) << mesh.error().message;
	auto simple = simplifyMesh(*mesh, kErrorMm);
	ASSERT_TRUE(simple) << simple.error().message;
	const Mesh &s = simple->mesh;
	std::printf("%s: %zu -> %zu faces, %zu -> %zu vertices, error %.2f mm\n", GetParam(), mesh->faces.size(),
		    s.faces.size(), mesh->vertices.size(), s.vertices.size(), simple->errorMm);
	EXPECT_LT(s.faces.size(), mesh->faces.size() / 2);
	EXPECT_LE(simple->errorMm, kErrorMm);
	for (const auto &f : s.faces)
		for (uint32_t i : f)
			ASSERT_LT(i, s.vertices.size());
	// Closed once its few faces the wrong way round are turned (the can's
	// simplified mesh has a pinch too), so its back faces can be skipped.
	Mesh oriented = s;
	EXPECT_TRUE(orientClosedOutward(oriented));
	// Three views at 1 m: the silhouettes and depths agree.
	for (const Eigen::Vector3d &axis : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 1), Eigen::Vector3d(1, 1, 0)}) {
		Pose p;
		p.R = Eigen::AngleAxisd(1.2, axis.normalized()).toRotationMatrix();
		p.t = Eigen::Vector3d(0, 0, 1000);
		const Agreement g = compareRenders(*mesh, s, p);
		EXPECT_GT(g.iou, 0.98) << axis.transpose();
		EXPECT_LT(g.meanAbsMm, 0.6) << axis.transpose();
		std::printf("  iou %.4f mean %.3f mm p99 %.2f mm\n", g.iou, g.meanAbsMm, g.p99AbsMm);
		EXPECT_LT(g.p99AbsMm, 3.5) << axis.transpose(); // silhouette pixels at grazing angles
		const Agreement culled = compareRenders(s, oriented, p, true);
		EXPECT_GT(culled.iou, 0.999) << axis.transpose();
		EXPECT_LT(culled.meanAbsMm, 0.01) << axis.transpose();
	}
}

INSTANTIATE_TEST_SUITE_P(LmoMeshes, RenderMesh, ::testing::Values("obj_000005.ply", "obj_000001.ply"));

TEST(RenderMeshInput, BadInputIsRefusedWithAReason)
{
	Mesh empty;
	auto r = simplifyMesh(empty, 1.0f);
	ASSERT_FALSE(r);
	EXPECT_NE(std::string(r.error().message).find("empty"), std::string::npos);
	Mesh tri;
	tri.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}};
	tri.faces = {{0, 1, 2}};
	EXPECT_FALSE(simplifyMesh(tri, 0.0f)); // no bound
	tri.faces = {{0, 1, 7}};
	r = simplifyMesh(tri, 1.0f);
	ASSERT_FALSE(r);
	EXPECT_NE(std::string(r.error().message).find("out of range"), std::string::npos);
}

} // namespace
} // namespace ihf
