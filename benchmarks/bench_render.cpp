// SPDX-License-Identifier: MIT
// DepthRenderer speed: LM-O "can" (obj 5, 45k faces) at its ground-truth pose
// (~1 m) into the full 640x480 image and into a 160x160 window around it, a
// 20k-face sphere, and a floor crossing the near plane (clipping path).
//
// Run: build-*/bin/bench_render [--benchmark_filter=...]

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <benchmark/benchmark.h>

#include "core/geometry/ply_loader.h"
#include "core/render/depth_renderer.h"

#ifndef IHF_SHARED_DIR
#define IHF_SHARED_DIR "../shared"
#endif

namespace ihf {
namespace {

CameraIntrinsics lmoCamera()
{
	return kinectV1Intrinsics();
}

const Mesh &canMesh()
{
	static const Mesh mesh = [] {
		const auto path = std::filesystem::path(IHF_SHARED_DIR) / "data/lmo/models/obj_000005.ply";
		auto m = loadPly(path);
		if (!m) {
			std::fprintf(stderr, "bench_render: %s\n", m.error().message.c_str());
			std::exit(1);
		}
		return std::move(m).value();
	}();
	return mesh;
}

Pose canPose()
{
	Pose p;
	p.R << 0.94893088, 0.30725587, -0.07208124, 0.24200515, -0.85502122, -0.45872652, -0.20257109, 0.41784038,
		-0.88568011;
	p.t = {134.36598053, 45.77287271, 964.78389285};
	return p;
}

// UV sphere, 20k faces, radius 50 mm (the tests use an icosphere; for speed
// only the face count and size matter).
Mesh sphereMesh()
{
	Mesh m;
	const int rings = 71, segments = 144;
	for (int i = 0; i <= rings; ++i) {
		const double th = M_PI * i / rings;
		for (int j = 0; j < segments; ++j) {
			const double ph = 2 * M_PI * j / segments;
			m.vertices.push_back(
				(50.0 * Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)))
					.cast<float>());
		}
	}
	for (int i = 0; i < rings; ++i) {
		for (int j = 0; j < segments; ++j) {
			uint32_t a = i * segments + j, b = i * segments + (j + 1) % segments;
			uint32_t c = a + segments, d = b + segments;
			m.faces.push_back({a, b, d});
			m.faces.push_back({a, d, c});
		}
	}
	return m;
}

void renderLoop(benchmark::State &state, const Mesh &mesh, const Pose &pose, int w, int h, RenderWindow window)
{
	const CameraIntrinsics K = lmoCamera();
	DepthRenderer renderer(mesh.vertices.size());
	DepthImageMm depth(w, h);
	RenderStats last;
	for (auto _ : state) {
		depth.view().fill(0.0f);
		auto stats = renderer.render(mesh, pose, K, depth.view(), {}, 0, window);
		if (!stats) {
			state.SkipWithError(stats.error().message.c_str());
			return;
		}
		last = *stats;
		benchmark::DoNotOptimize(depth.data());
	}
	state.counters["faces"] = static_cast<double>(mesh.faces.size());
	state.counters["pixels"] = last.pixelsWritten;
	state.counters["drawn"] = last.trianglesDrawn;
}

void BM_CanFull(benchmark::State &state)
{
	renderLoop(state, canMesh(), canPose(), 640, 480, {});
}
BENCHMARK(BM_CanFull)->Unit(benchmark::kMillisecond);

void BM_CanWindow160(benchmark::State &state)
{
	// bbox_obj of the can is (376, 226, 60, 91): a 160x160 crop around it.
	renderLoop(state, canMesh(), canPose(), 160, 160, {326, 192});
}
BENCHMARK(BM_CanWindow160)->Unit(benchmark::kMillisecond);

void BM_CanNear(benchmark::State &state)
{
	// Close up (400 mm): more pixels per triangle.
	Pose p = canPose();
	p.t = {0, 0, 400};
	renderLoop(state, canMesh(), p, 640, 480, {});
}
BENCHMARK(BM_CanNear)->Unit(benchmark::kMillisecond);

void BM_Sphere(benchmark::State &state)
{
	static const Mesh sphere = sphereMesh();
	Pose p;
	p.t = {0, 0, 700};
	renderLoop(state, sphere, p, 640, 480, {});
}
BENCHMARK(BM_Sphere)->Unit(benchmark::kMillisecond);

void BM_FloorClipped(benchmark::State &state)
{
	Mesh floor;
	floor.vertices = {{-3000, 100, -1000}, {3000, 100, -1000}, {3000, 100, 3000}, {-3000, 100, 3000}};
	floor.faces = {{0, 1, 2}, {0, 2, 3}};
	renderLoop(state, floor, Pose{}, 640, 480, {});
}
BENCHMARK(BM_FloorClipped)->Unit(benchmark::kMillisecond);

} // namespace
} // namespace ihf
