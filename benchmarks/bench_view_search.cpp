// SPDX-License-Identifier: MIT
// View-template rotation search (core/pose/view_search.h): building the
// templates of the LM-O ape at load (320 directions x 128 points, the
// default), and one search at a translation (320 x 24 rotations) on a
// render of the ape before a wall: with and without the box-centred
// translation, coarse-to-fine (default) or one pass on all points, and
// the frame budget's cheaper search (budget:1), at the voted centre or
// (anchored:1) on the box's ray at a depth, as a depth centre is searched.
//
// Run: build/bin/bench_view_search [--benchmark_filter=...]

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/pose.h"
#include "core/pose/view_search.h"
#include "core/render/depth_renderer.h"
#include "core/training/view_template_builder.h"

#ifndef IHF_SHARED_DIR
#define IHF_SHARED_DIR "../shared"
#endif

namespace ihf {
namespace {

const Mesh &apeMesh()
{
	static const Mesh mesh = [] {
		auto m = loadPly(std::filesystem::path(IHF_SHARED_DIR) / "data/lmo/models/obj_000001.ply");
		if (!m) {
			std::fprintf(stderr, "bench_view_search: %s\n", m.error().message.c_str());
			std::exit(1);
		}
		return std::move(m).value();
	}();
	return mesh;
}

void BM_BuildViewTemplates(benchmark::State &state)
{
	const Mesh &mesh = apeMesh();
	const double diameter = meshDiameter(mesh);
	const ViewTemplateConfig cfg{static_cast<int>(state.range(0)), 128};
	for (auto _ : state) {
		auto pts = buildViewTemplatePoints(mesh, diameter, cfg);
		if (!pts) {
			state.SkipWithError(pts.error().message.c_str());
			return;
		}
		benchmark::DoNotOptimize(pts->data());
	}
	state.counters["bytes"] = static_cast<double>(cfg.viewpoints) * cfg.pointsPerView * sizeof(Eigen::Vector3f);
}
BENCHMARK(BM_BuildViewTemplates)->Arg(320)->Arg(160)->Unit(benchmark::kMillisecond);

void BM_SearchViews(benchmark::State &state)
{
	const Mesh &mesh = apeMesh();
	const double diameter = meshDiameter(mesh);
	auto pts = buildViewTemplatePoints(mesh, diameter, {320, 128});
	if (!pts) {
		state.SkipWithError(pts.error().message.c_str());
		return;
	}
	auto budgetPts = buildViewTemplatePoints(mesh, diameter, {160, 128});
	if (!budgetPts) {
		state.SkipWithError(budgetPts.error().message.c_str());
		return;
	}
	const ViewTemplates fullTemplates{320, 128, *pts};
	const ViewTemplates budgetTemplates{160, 128, *budgetPts};
	const CameraIntrinsics K = kinectV1Intrinsics();
	Pose truth;
	truth.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix();
	truth.t = {0, 0, 900};
	std::vector<float> depth(static_cast<size_t>(K.width) * K.height, 0.0f);
	DepthRenderer renderer(mesh.vertices.size());
	if (!renderer.render(mesh, truth, K, ImageView<float>(depth.data(), K.width, K.height, K.width))) {
		state.SkipWithError("render failed");
		return;
	}
	for (float &d : depth)
		if (!(d > 0))
			d = 1150.0f;
	ViewSearchConfig cfg;
	cfg.boxCentre = state.range(0) != 0;
	if (state.range(1) == 0)
		cfg.coarsePoints = 0;
	// The frame budget's search (config/device.toml's settings on the
	// budget's templates: 160 directions).
	const bool budget = state.range(2) != 0;
	if (budget)
		cfg = underBudget(cfg);
	const ViewTemplates templates = budget ? budgetTemplates : fullTemplates;
	ViewProposal top[6];
	const bool anchored = state.range(3) != 0;
	const Eigen::Vector3d centre = anchored ? Eigen::Vector3d::Zero() : Eigen::Vector3d(truth.t + Eigen::Vector3d(0, 0, 20));
	const float anchor = anchored ? static_cast<float>(truth.t.z()) : 0.0f;
	for (auto _ : state) {
		size_t n = searchViews(templates, cfg, ImageView<const float>(depth.data(), K.width, K.height, K.width),
				       K, centre, std::span<ViewProposal>(top, 6), {}, anchor);
		benchmark::DoNotOptimize(n);
	}
	state.counters["rotations"] = viewSearchSize(templates, cfg);
}
BENCHMARK(BM_SearchViews)
	->ArgNames({"box_centre", "coarse", "budget", "anchored"})
	->Args({1, 1, 0, 0})
	->Args({1, 0, 0, 0})
	->Args({0, 1, 0, 0})
	->Args({0, 0, 0, 0})
	->Args({1, 1, 1, 0})
	->Args({1, 1, 0, 1})
	->Args({1, 1, 1, 1})
	->Unit(benchmark::kMillisecond);

} // namespace
} // namespace ihf
