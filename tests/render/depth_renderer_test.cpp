// SPDX-License-Identifier: MIT
// DepthRenderer against analytic geometry: planes, a sphere, the fill rule,
// the z-buffer, near-plane clipping, windows and argument errors.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/geometry/ply_loader.h"
#include "core/render/depth_renderer.h"
#include "tests/common/test_paths.h"
#include "tests/render/test_shapes.h"

namespace ihf {
namespace {

CameraIntrinsics lmoCamera()
{
	CameraIntrinsics K;
	K.fx = 572.4114;
	K.fy = 573.57043;
	K.cx = 325.2611;
	K.cy = 242.04899;
	K.width = 640;
	K.height = 480;
	return K;
}

// Camera where image coordinates equal model millimetres on the plane z = 100.
CameraIntrinsics unitCamera()
{
	CameraIntrinsics K;
	K.fx = K.fy = 100;
	K.cx = K.cy = 0;
	K.width = K.height = 64;
	return K;
}

Pose makePose(const Eigen::Vector3d &axis, double angleDeg, const Eigen::Vector3d &t)
{
	Pose p;
	p.R = Eigen::AngleAxisd(angleDeg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
	p.t = t;
	return p;
}

Eigen::Vector3d rayDir(const CameraIntrinsics &K, double u, double v)
{
	return {(u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0};
}

// Calls f(u, v) for the pixel centre and four points 0.02 px around it;
// true if f agrees on all of them (the pixel is not on a boundary).
bool unambiguous(double u, double v, const std::function<bool(double, double)> &f)
{
	const bool c = f(u, v);
	const double e = 0.02;
	return f(u + e, v) == c && f(u - e, v) == c && f(u, v + e) == c && f(u, v - e) == c;
}

TEST(DepthRenderer, TiltedPlaneMatchesRayPlaneIntersection)
{
	const CameraIntrinsics K = lmoCamera();
	const float h = 200.0f;
	const Mesh plane = test::quad({-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0});
	const Pose pose = makePose({1, 1, 0.3}, 50, {20, -10, 800});
	const Eigen::Vector3d n = pose.R.col(2);

	DepthRenderer r(4);
	DepthImageMm depth(640, 480);
	auto stats = r.render(plane, pose, K, depth.view());
	ASSERT_TRUE(stats.ok()) << stats.error().message;
	EXPECT_EQ(stats->trianglesDrawn, 2);

	// Model-space hit of the ray through (u, v) and whether it is on the quad.
	auto hit = [&](double u, double v, double &z) {
		const Eigen::Vector3d d = rayDir(K, u, v);
		z = n.dot(pose.t) / n.dot(d);
		const Eigen::Vector3d m = pose.R.transpose() * (z * d - pose.t);
		return std::abs(m.x()) <= h && std::abs(m.y()) <= h;
	};
	int checked = 0, covered = 0;
	double maxErr = 0;
	for (int v = 0; v < 480; ++v) {
		for (int u = 0; u < 640; ++u) {
			double z;
			const bool inside = hit(u, v, z);
			if (!unambiguous(u, v, [&](double uu, double vv) { double zz; return hit(uu, vv, zz); }))
				continue;
			++checked;
			const float d = depth.at(u, v);
			if (!inside) {
				ASSERT_EQ(d, 0.0f) << u << "," << v;
				continue;
			}
			ASSERT_GT(d, 0.0f) << u << "," << v;
			maxErr = std::max(maxErr, std::abs(d - z));
			++covered;
		}
	}
	EXPECT_GT(covered, 50000);
	EXPECT_GT(checked, 300000);
	EXPECT_LT(maxErr, 1e-3);
	RecordProperty("max_depth_error_mm", std::to_string(maxErr));
}

TEST(DepthRenderer, SphereMatchesAnalyticDepthAndSilhouette)
{
	const CameraIntrinsics K = lmoCamera();
	const double radius = 50;
	const Mesh sphere = test::icosphere(static_cast<float>(radius), 5); // 20480 faces
	ASSERT_EQ(sphere.faces.size(), 20480u);
	const Eigen::Vector3d c(30, -20, 700);
	Pose pose = makePose({0.2, 1, 0.1}, 17, c); // rotation must not matter

	DepthRenderer r(sphere.vertices.size());
	DepthImageMm depth(640, 480);
	ASSERT_TRUE(r.render(sphere, pose, K, depth.view()).ok());

	// Half a pixel at the sphere's distance, in mm.
	const double margin = 1.3 * c.z() / K.fx;
	double maxErr = 0, maxErrFacing = 0;
	int inner = 0;
	for (int v = 0; v < 480; ++v) {
		for (int u = 0; u < 640; ++u) {
			const Eigen::Vector3d d = rayDir(K, u, v).normalized();
			const double b = d.dot(c);
			const double dist = std::sqrt(std::max(0.0, c.squaredNorm() - b * b));
			const float got = depth.at(u, v);
			if (dist > radius + margin) {
				ASSERT_EQ(got, 0.0f) << u << "," << v;
				continue;
			}
			if (dist > radius - margin)
				continue; // silhouette band
			ASSERT_GT(got, 0.0f) << u << "," << v;
			const double s = b - std::sqrt(radius * radius - dist * dist);
			const double z = s * d.z();
			// The mesh is inscribed: never in front of the sphere.
			const double err = got - z;
			ASSERT_GT(err, -1e-3) << u << "," << v;
			maxErr = std::max(maxErr, err);
			const double cosAngle = std::sqrt(1.0 - (dist / radius) * (dist / radius));
			if (cosAngle > 0.5)
				maxErrFacing = std::max(maxErrFacing, err);
			++inner;
		}
	}
	EXPECT_GT(inner, 4000); // the disc is ~5300 px
	EXPECT_LT(maxErr, 0.5);
	RecordProperty("max_depth_error_mm", std::to_string(maxErr));
	RecordProperty("max_depth_error_facing_mm", std::to_string(maxErrFacing));
	// Sagitta of the level-5 tessellation is ~0.01 mm.
	EXPECT_LT(maxErrFacing, 0.05);
}

TEST(DepthRenderer, WindingDoesNotMatter)
{
	const CameraIntrinsics K = lmoCamera();
	Mesh sphere = test::icosphere(40, 3);
	const Pose pose = makePose({1, 0, 0}, 10, {-15, 10, 500});
	DepthRenderer r(sphere.vertices.size());
	DepthImageMm a(640, 480), b(640, 480);
	ASSERT_TRUE(r.render(sphere, pose, K, a.view()).ok());
	for (auto &f : sphere.faces)
		std::swap(f[1], f[2]);
	ASSERT_TRUE(r.render(sphere, pose, K, b.view()).ok());
	EXPECT_EQ(std::memcmp(a.data(), b.data(), 640 * 480 * sizeof(float)), 0);
}

TEST(DepthRenderer, TopLeftFillRule)
{
	const CameraIntrinsics K = unitCamera();
	Mesh tri;
	// Corners on pixel centres; the hypotenuse passes through centres too.
	tri.vertices = {{0, 0, 100}, {4, 0, 100}, {0, 4, 100}};
	tri.faces = {{0, 1, 2}};
	DepthRenderer r(3);
	for (int flip = 0; flip < 2; ++flip) {
		if (flip)
			tri.faces = {{0, 2, 1}};
		DepthImageMm depth(16, 16);
		auto stats = r.render(tri, Pose{}, K, depth.view(), {}, 0, {-4, -4});
		ASSERT_TRUE(stats.ok());
		EXPECT_EQ(stats->pixelsWritten, 10); // x, y >= 0 and x + y < 4
		for (int y = -4; y < 12; ++y)
			for (int x = -4; x < 12; ++x)
				EXPECT_EQ(depth.at(x + 4, y + 4) > 0, x >= 0 && y >= 0 && x + y < 4) << x << "," << y;
	}
}

TEST(DepthRenderer, SharedEdgesCoverEachPixelOnce)
{
	// A 32x32 mm square at z = 100 (32x32 pixels) split into jittered cells
	// with vertices on pixel centres, so many centres lie exactly on edges.
	const CameraIntrinsics K = unitCamera();
	std::mt19937 rng(3);
	std::uniform_int_distribution<int> jitter(-1, 1);
	Mesh grid;
	const int cells = 8, step = 4;
	for (int j = 0; j <= cells; ++j) {
		for (int i = 0; i <= cells; ++i) {
			int x = i * step, y = j * step;
			if (i > 0 && i < cells)
				x += jitter(rng);
			if (j > 0 && j < cells)
				y += jitter(rng);
			grid.vertices.push_back(Eigen::Vector3f(x, y, 100));
		}
	}
	std::vector<std::array<uint32_t, 3>> faces;
	for (int j = 0; j < cells; ++j) {
		for (int i = 0; i < cells; ++i) {
			uint32_t a = j * (cells + 1) + i, b = a + 1, c = a + cells + 1, d = c + 1;
			if ((i + j) % 2) {
				faces.push_back({a, b, d});
				faces.push_back({a, d, c});
			} else {
				faces.push_back({a, b, c});
				faces.push_back({b, d, c});
			}
		}
	}
	DepthRenderer r(grid.vertices.size());
	std::vector<int> count(40 * 40, 0);
	int written = 0;
	for (const auto &f : faces) {
		grid.faces = {f};
		DepthImageMm depth(40, 40);
		auto stats = r.render(grid, Pose{}, K, depth.view(), {}, 0, {-4, -4});
		ASSERT_TRUE(stats.ok());
		written += stats->pixelsWritten;
		for (int i = 0; i < 40 * 40; ++i)
			count[i] += depth.data()[i] > 0;
	}
	EXPECT_EQ(written, 32 * 32);
	for (int y = -4; y < 36; ++y)
		for (int x = -4; x < 36; ++x)
			ASSERT_EQ(count[(y + 4) * 40 + x + 4], (x >= 0 && x < 32 && y >= 0 && y < 32) ? 1 : 0) << x << "," << y;
}

// Sub-pixel triangles (one pixel centre in their box) take a shortcut in the
// renderer; it must apply the same rule.
TEST(DepthRenderer, TopLeftFillRuleForSubPixelTriangles)
{
	const CameraIntrinsics K = unitCamera();
	DepthRenderer r(3);
	struct Case {
		Eigen::Vector3f a, b, c;
		bool covered; // pixel (0, 0), which lies on the edge a-b
	};
	for (const Case &t : {Case{{-0.5f, 0, 100}, {0.5f, 0, 100}, {0, 0.7f, 100}, true},   // top edge
			      Case{{-0.5f, 0, 100}, {0.5f, 0, 100}, {0, -0.7f, 100}, false}, // bottom edge
			      Case{{0, -0.5f, 100}, {0, 0.5f, 100}, {0.7f, 0, 100}, true},   // left edge
			      Case{{0, -0.5f, 100}, {0, 0.5f, 100}, {-0.7f, 0, 100}, false}, // right edge
			      Case{{-0.4f, -0.3f, 100}, {0.4f, 0.3f, 100}, {-0.4f, 0.4f, 100}, false}, // upper right
			      Case{{-0.4f, -0.3f, 100}, {0.4f, 0.3f, 100}, {0.4f, -0.4f, 100}, true}}) { // lower left
		for (int flip = 0; flip < 2; ++flip) {
			Mesh m;
			m.vertices = {t.a, t.b, t.c};
			m.faces = {flip ? std::array<uint32_t, 3>{0, 2, 1} : std::array<uint32_t, 3>{0, 1, 2}};
			DepthImageMm depth(4, 4);
			auto stats = r.render(m, Pose{}, K, depth.view(), {}, 0, {-2, -2});
			ASSERT_TRUE(stats.ok());
			int covered = 0;
			for (float d : depth.pixels())
				covered += d > 0;
			EXPECT_EQ(covered, t.covered ? 1 : 0) << t.c.transpose();
			EXPECT_EQ(depth.at(2, 2) > 0, t.covered) << t.c.transpose();
		}
	}

	// A grid of 1-pixel cells centred on pixel centres, split by diagonals
	// through those centres: every pixel exactly once.
	Mesh grid;
	const int n = 12;
	for (int j = 0; j <= n; ++j)
		for (int i = 0; i <= n; ++i)
			grid.vertices.push_back(Eigen::Vector3f(i - 0.5f, j - 0.5f, 100));
	std::vector<std::array<uint32_t, 3>> faces;
	for (int j = 0; j < n; ++j) {
		for (int i = 0; i < n; ++i) {
			uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
			if ((i + j) % 2) {
				faces.push_back({a, b, d});
				faces.push_back({a, d, c});
			} else {
				faces.push_back({a, b, c});
				faces.push_back({b, d, c});
			}
		}
	}
	DepthRenderer gr(grid.vertices.size());
	std::vector<int> count(16 * 16, 0);
	for (const auto &f : faces) {
		grid.faces = {f};
		DepthImageMm depth(16, 16);
		ASSERT_TRUE(gr.render(grid, Pose{}, K, depth.view(), {}, 0, {-2, -2}).ok());
		for (int i = 0; i < 16 * 16; ++i)
			count[i] += depth.data()[i] > 0;
	}
	for (int y = -2; y < 14; ++y)
		for (int x = -2; x < 14; ++x)
			ASSERT_EQ(count[(y + 2) * 16 + x + 2], (x >= 0 && x < n && y >= 0 && y < n) ? 1 : 0) << x << "," << y;
}

TEST(DepthRenderer, NearerSurfaceWinsWhateverTheOrder)
{
	const CameraIntrinsics K = lmoCamera();
	// A fronto-parallel square and a tilted one cutting through it.
	const Mesh front = test::quad({-60, -60, 0}, {60, -60, 0}, {60, 60, 0}, {-60, 60, 0});
	const Pose frontPose = makePose({0, 0, 1}, 0, {0, 0, 700});
	const Mesh tilted = test::quad({-40, -80, 0}, {120, -80, 0}, {120, 80, 0}, {-40, 80, 0});
	const Pose tiltedPose = makePose({0, 1, 0}, 40, {10, 5, 710});

	auto planeHit = [&](const Pose &p, float hx0, float hx1, float hy, double u, double v, double &z) {
		const Eigen::Vector3d n = p.R.col(2), d = rayDir(K, u, v);
		z = n.dot(p.t) / n.dot(d);
		const Eigen::Vector3d m = p.R.transpose() * (z * d - p.t);
		return m.x() >= hx0 && m.x() <= hx1 && std::abs(m.y()) <= hy;
	};
	// 1 = front, 2 = tilted, 0 = none.
	auto expected = [&](double u, double v, double &z) {
		double z1, z2;
		const bool in1 = planeHit(frontPose, -60, 60, 60, u, v, z1);
		const bool in2 = planeHit(tiltedPose, -40, 120, 80, u, v, z2);
		if (in1 && (!in2 || z1 < z2)) {
			z = z1;
			return 1;
		}
		z = z2;
		return in2 ? 2 : 0;
	};

	DepthRenderer r(4);
	for (int order = 0; order < 2; ++order) {
		DepthImageMm depth(640, 480);
		Image<uint16_t> label(640, 480);
		if (order == 0) {
			ASSERT_TRUE(r.render(front, frontPose, K, depth.view(), label.view(), 1).ok());
			ASSERT_TRUE(r.render(tilted, tiltedPose, K, depth.view(), label.view(), 2).ok());
		} else {
			ASSERT_TRUE(r.render(tilted, tiltedPose, K, depth.view(), label.view(), 2).ok());
			ASSERT_TRUE(r.render(front, frontPose, K, depth.view(), label.view(), 1).ok());
		}
		int seen[3] = {0, 0, 0};
		for (int v = 0; v < 480; ++v) {
			for (int u = 0; u < 640; ++u) {
				double z;
				const int want = expected(u, v, z);
				if (!unambiguous(u, v, [&](double uu, double vv) { double zz; return expected(uu, vv, zz) == want; }))
					continue;
				double z1, z2;
				if (planeHit(frontPose, -60, 60, 60, u, v, z1) && planeHit(tiltedPose, -40, 120, 80, u, v, z2) &&
				    std::abs(z1 - z2) < 0.01)
					continue; // on the intersection line
				ASSERT_EQ(label.at(u, v), want) << u << "," << v << " order " << order;
				if (want)
					ASSERT_NEAR(depth.at(u, v), z, 1e-3) << u << "," << v;
				else
					ASSERT_EQ(depth.at(u, v), 0.0f);
				++seen[want];
			}
		}
		EXPECT_GT(seen[1], 5000);
		EXPECT_GT(seen[2], 5000);
	}
}

// A floor reaching from behind the camera to 3 m, 100 mm below the optical
// axis. Without near-plane clipping its far-behind corners would project
// to mirrored positions; clipped vertices project millions of pixels off
// the image and exercise the guard-band path as well.
TEST(DepthRenderer, FloorThroughNearPlaneIsClipped)
{
	const CameraIntrinsics K = lmoCamera();
	const Mesh floor = test::quad({-3000, 100, -1000}, {3000, 100, -1000}, {3000, 100, 3000}, {-3000, 100, 3000});
	for (float nearMm : {1.0f, 400.0f}) {
		SCOPED_TRACE(nearMm);
		DepthRenderer r(4);
		r.setNearPlane(nearMm);
		DepthImageMm depth(640, 480);
		auto stats = r.render(floor, Pose{}, K, depth.view());
		ASSERT_TRUE(stats.ok());
		EXPECT_EQ(stats->trianglesDrawn, 2);
		auto hit = [&](double u, double v, double &z) {
			const Eigen::Vector3d d = rayDir(K, u, v);
			if (d.y() <= 0)
				return false;
			z = 100.0 / d.y();
			return z >= nearMm && z <= 3000 && std::abs(z * d.x()) <= 3000;
		};
		int covered = 0, empty = 0;
		for (int v = 0; v < 480; ++v) {
			for (int u = 0; u < 640; ++u) {
				double z = 0;
				const bool in = hit(u, v, z);
				if (!unambiguous(u, v, [&](double uu, double vv) { double zz; return hit(uu, vv, zz); }))
					continue;
				if (in) {
					ASSERT_NEAR(depth.at(u, v), z, 1e-3 + 2e-7 * z) << u << "," << v;
					++covered;
				} else {
					ASSERT_EQ(depth.at(u, v), 0.0f) << u << "," << v;
					++empty;
				}
			}
		}
		// Rows below the far edge (v > 261): 139k px; with near = 400 only
		// up to v = 385: 79k px.
		EXPECT_GT(covered, nearMm < 100 ? 130000 : 75000);
		EXPECT_GT(empty, 100000);
	}
}

TEST(DepthRenderer, GeometryBehindTheCameraDrawsNothing)
{
	const CameraIntrinsics K = lmoCamera();
	Mesh m = test::quad({-500, -500, -10}, {500, -500, -10}, {500, 500, -300}, {-500, 500, -300});
	// And one triangle with a vertex exactly on the camera centre.
	m.vertices.push_back({0, 0, 0});
	m.faces.push_back({0, 1, 4});
	DepthRenderer r(5);
	DepthImageMm depth(640, 480);
	auto stats = r.render(m, Pose{}, K, depth.view());
	ASSERT_TRUE(stats.ok());
	EXPECT_EQ(stats->pixelsWritten, 0);
	EXPECT_EQ(stats->trianglesCulled, 3);
	for (float d : depth.pixels())
		ASSERT_EQ(d, 0.0f);
}

TEST(DepthRenderer, DegenerateFacesAreSkipped)
{
	const CameraIntrinsics K = lmoCamera();
	Mesh m;
	m.vertices = {{0, 0, 500}, {50, 0, 500}, {100, 0, 500}, {0, 50, 500}};
	m.faces = {{0, 0, 3}, {0, 1, 2}, {3, 3, 3}};
	DepthRenderer r(4);
	DepthImageMm depth(640, 480);
	auto stats = r.render(m, Pose{}, K, depth.view());
	ASSERT_TRUE(stats.ok());
	EXPECT_EQ(stats->trianglesDrawn, 0);
	EXPECT_EQ(stats->trianglesCulled, 3);
	EXPECT_EQ(stats->pixelsWritten, 0);
}

// Windows, including ones hanging off the image, must equal the same region
// of a larger render bit for bit, for meshes on the plain and clipped paths.
TEST(DepthRenderer, WindowEqualsRegionOfFullRender)
{
	const CameraIntrinsics K = lmoCamera();
	auto can = loadPly(test::lmoDir() / "models" / "obj_000005.ply");
	ASSERT_TRUE(can.ok()) << can.error().message;
	Pose canPose;
	canPose.R << 0.94893088, 0.30725587, -0.07208124, 0.24200515, -0.85502122, -0.45872652, -0.20257109,
		0.41784038, -0.88568011;
	canPose.t = {134.36598053, 45.77287271, 964.78389285};
	const Mesh sphere = test::icosphere(60, 4);
	const Pose spherePose = makePose({0, 1, 0}, 0, {-80, -30, 600});
	const Mesh floor = test::quad({-3000, 100, -1000}, {3000, 100, -1000}, {3000, 100, 3000}, {-3000, 100, 3000});

	DepthRenderer r(can->vertices.size());
	auto draw = [&](ImageView<float> d, ImageView<uint16_t> l, RenderWindow w) {
		ASSERT_TRUE(r.render(floor, Pose{}, K, d, l, 1, w).ok());
		ASSERT_TRUE(r.render(*can, canPose, K, d, l, 5, w).ok());
		ASSERT_TRUE(r.render(sphere, spherePose, K, d, l, 9, w).ok());
	};
	// Reference: image plus 100 px all round.
	const int ox = -100, oy = -100;
	DepthImageMm ref(840, 680);
	Image<uint16_t> refLabel(840, 680);
	draw(ref.view(), refLabel.view(), {ox, oy});
	int labelled[10] = {};
	for (uint16_t l : refLabel.pixels())
		++labelled[l];
	ASSERT_GT(labelled[1], 10000);
	ASSERT_GT(labelled[5], 2000);
	ASSERT_GT(labelled[9], 2000);

	struct Box {
		int x0, y0, w, h;
	};
	for (const Box &b : {Box{0, 0, 640, 480}, Box{370, 220, 160, 160}, Box{-40, -30, 100, 90}, Box{600, 420, 120, 100},
			     Box{233, 111, 1, 1}, Box{401, 250, 37, 53}, Box{-100, 300, 840, 7}}) {
		SCOPED_TRACE(testing::Message() << b.x0 << "," << b.y0 << " " << b.w << "x" << b.h);
		DepthImageMm d(b.w, b.h);
		Image<uint16_t> l(b.w, b.h);
		draw(d.view(), l.view(), {b.x0, b.y0});
		for (int y = 0; y < b.h; ++y) {
			ASSERT_EQ(std::memcmp(&d.at(0, y), &ref.at(b.x0 - ox, b.y0 + y - oy), b.w * sizeof(float)), 0) << y;
			ASSERT_EQ(std::memcmp(&l.at(0, y), &refLabel.at(b.x0 - ox, b.y0 + y - oy), b.w * sizeof(uint16_t)), 0);
		}
	}
	// A strided view into the middle of a bigger buffer works the same.
	DepthImageMm big(300, 300, -1.0f);
	ImageView<float> sub(&big.at(50, 60), 160, 160, 300);
	sub.fill(0.0f);
	ASSERT_TRUE(r.render(*can, canPose, K, sub, {}, 0, {370, 220}).ok());
	DepthImageMm alone(160, 160);
	ASSERT_TRUE(r.render(*can, canPose, K, alone.view(), {}, 0, {370, 220}).ok());
	for (int y = 0; y < 160; ++y)
		ASSERT_EQ(std::memcmp(&alone.at(0, y), &sub.at(0, y), 160 * sizeof(float)), 0);
	EXPECT_EQ(big.at(49, 60), -1.0f);
	EXPECT_EQ(big.at(210, 60), -1.0f);
	EXPECT_EQ(big.at(50, 59), -1.0f);
	EXPECT_EQ(big.at(50, 220), -1.0f);
}

TEST(DepthRenderer, ErrorsLeaveBuffersUntouched)
{
	const CameraIntrinsics K = lmoCamera();
	const Mesh sphere = test::icosphere(50, 1); // 42 vertices
	const Pose pose = makePose({0, 0, 1}, 0, {0, 0, 500});
	DepthImageMm depth(64, 48, 123.0f);
	Image<uint16_t> label(64, 48, 7);
	auto untouched = [&] {
		for (float d : depth.pixels())
			if (d != 123.0f)
				return false;
		for (uint16_t l : label.pixels())
			if (l != 7)
				return false;
		return true;
	};

	DepthRenderer small(10);
	auto a = small.render(sphere, pose, K, depth.view(), label.view(), 1, {290, 220});
	ASSERT_FALSE(a.ok());
	EXPECT_EQ(a.error().code, Errc::kCapacity);
	EXPECT_TRUE(untouched());

	DepthRenderer r;
	EXPECT_EQ(r.capacity(), 0u);
	r.reserve(sphere.vertices.size());
	EXPECT_EQ(r.capacity(), sphere.vertices.size());

	Mesh bad = sphere;
	bad.faces.back()[2] = static_cast<uint32_t>(bad.vertices.size());
	auto b = r.render(bad, pose, K, depth.view(), label.view(), 1, {290, 220});
	ASSERT_FALSE(b.ok());
	EXPECT_EQ(b.error().code, Errc::kOutOfRange);

	Image<uint16_t> wrongLabel(10, 10);
	auto c = r.render(sphere, pose, K, depth.view(), wrongLabel.view(), 1);
	ASSERT_FALSE(c.ok());
	EXPECT_EQ(c.error().code, Errc::kInvalidArgument);

	auto d = r.render(sphere, pose, K, depth.view(), label.view(), 1, {9000, 0});
	ASSERT_FALSE(d.ok());
	EXPECT_EQ(d.error().code, Errc::kInvalidArgument);

	CameraIntrinsics badK = K;
	badK.fx = 0;
	EXPECT_FALSE(r.render(sphere, pose, badK, depth.view()).ok());

	r.setNearPlane(0.0f);
	EXPECT_FALSE(r.render(sphere, pose, K, depth.view()).ok());
	EXPECT_TRUE(untouched());

	// The same calls succeed once the problem is gone.
	r.setNearPlane(1.0f);
	depth.view().fill(0.0f);
	auto ok = r.render(sphere, pose, K, depth.view(), label.view(), 1, {290, 220});
	ASSERT_TRUE(ok.ok());
	EXPECT_GT(ok->pixelsWritten, 100);
}

// A closed mesh wound outwards, seen from outside: without its back faces
// the same pixels are covered at the same depth (up to grazing triangles'
// clamped depth at the silhouette), with about half the triangles drawn.
TEST(DepthRenderer, CullingAClosedMeshsBackFacesKeepsItsDepth)
{
	const CameraIntrinsics K = lmoCamera();
	auto ape = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	ASSERT_TRUE(ape.ok());
	const Mesh sphere = test::icosphere(50, 4);
	const Mesh &apeMesh = *ape;
	for (const Mesh *mesh : {&sphere, &apeMesh}) {
		ASSERT_TRUE(isClosedOutward(*mesh));
		for (int turn = 0; turn < 4; ++turn) {
			const Pose pose = makePose({0.3, 1, 0.2 * turn}, 40.0 * turn + 10, {20, -15, 650});
			DepthRenderer r(mesh->vertices.size());
			DepthImageMm all(640, 480), culled(640, 480);
			auto a = r.render(*mesh, pose, K, all.view());
			r.setCullBackFaces(true);
			auto c = r.render(*mesh, pose, K, culled.view());
			ASSERT_TRUE(a.ok() && c.ok());
			int covered = 0, differ = 0;
			float worst = 0;
			for (int v = 0; v < 480; ++v)
				for (int u = 0; u < 640; ++u) {
					ASSERT_EQ(all.at(u, v) > 0, culled.at(u, v) > 0) << u << "," << v;
					covered += all.at(u, v) > 0;
					const float d = std::abs(all.at(u, v) - culled.at(u, v));
					differ += d > 0;
					worst = std::max(worst, d);
				}
			EXPECT_GT(covered, 1000);
			EXPECT_LE(differ, covered / 100) << "turn " << turn;
			EXPECT_LT(worst, 1.0f) << "turn " << turn;
			EXPECT_LT(c->trianglesDrawn, a->trianglesDrawn * 6 / 10) << "turn " << turn;
		}
	}
}

// Drawing a mesh is drawing its faces in order, each depth-tested against
// what is there: a mesh of over a thousand faces (a sphere near and far, so
// that many faces are sub-pixel, and a floor through the near plane, which
// needs clipping), rendered into a window, gives exactly what drawing its
// faces one call at a time gives, with culling on and off, and the same
// counts. A guard for any reordering or batching of the faces.
TEST(DepthRenderer, OneCallEqualsItsFacesDrawnOneByOne)
{
	const CameraIntrinsics K = lmoCamera();
	Mesh mesh = test::icosphere(60, 3); // 1,280 faces
	const Mesh floor = test::quad({-3000, 100, -1000}, {3000, 100, -1000}, {3000, 100, 3000}, {-3000, 100, 3000});
	const auto base = static_cast<uint32_t>(mesh.vertices.size());
	for (const auto &v : floor.vertices)
		mesh.vertices.push_back(v);
	// The floor's faces among the sphere's.
	mesh.faces.insert(mesh.faces.begin() + 300, {floor.faces[0][0] + base, floor.faces[0][1] + base,
						      floor.faces[0][2] + base});
	mesh.faces.push_back({floor.faces[1][0] + base, floor.faces[1][1] + base, floor.faces[1][2] + base});
	const RenderWindow window{300, 150}; // cuts the near sphere
	for (const double z : {500.0, 4000.0}) {
		for (const bool cull : {false, true}) {
			SCOPED_TRACE(testing::Message() << "z " << z << ", cull " << cull);
			const Pose pose = makePose({0.2, 1, 0.1}, 25, {-10, 5, z});
			DepthRenderer r(mesh.vertices.size());
			r.setCullBackFaces(cull);
			DepthImageMm whole(240, 180), single(240, 180);
			Image<uint16_t> wholeLabel(240, 180), singleLabel(240, 180);
			auto all = r.render(mesh, pose, K, whole.view(), wholeLabel.view(), 7, window);
			ASSERT_TRUE(all.ok());
			Mesh one;
			one.vertices = mesh.vertices;
			one.faces.resize(1);
			RenderStats sum;
			for (const auto &f : mesh.faces) {
				one.faces[0] = f;
				auto s = r.render(one, pose, K, single.view(), singleLabel.view(), 7, window);
				ASSERT_TRUE(s.ok());
				sum.trianglesDrawn += s->trianglesDrawn;
				sum.trianglesCulled += s->trianglesCulled;
				sum.pixelsWritten += s->pixelsWritten;
			}
			EXPECT_EQ(all->trianglesDrawn, sum.trianglesDrawn);
			EXPECT_EQ(all->trianglesCulled, sum.trianglesCulled);
			EXPECT_EQ(all->pixelsWritten, sum.pixelsWritten);
			EXPECT_GT(all->trianglesDrawn, 100);
			EXPECT_GT(all->trianglesCulled, 100);
			EXPECT_EQ(0, std::memcmp(whole.data(), single.data(), whole.pixels().size_bytes()));
			EXPECT_EQ(0, std::memcmp(wholeLabel.data(), singleLabel.data(), wholeLabel.pixels().size_bytes()));
		}
	}
}

} // namespace
} // namespace ihf
