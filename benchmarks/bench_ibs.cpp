// SPDX-License-Identifier: MIT
// IBS fit and HoCP speed and quality. Clouds (2000 points used by the fit):
//   sphere: analytic depth render of a 60 mm sphere at 750 mm;
//   render: LM-O driller (obj 8) rendered at its ground-truth pose;
//   real:   the real Kinect crop of the driller (bbox_obj, clutter included)
//           from test/000002 image 3.
// Fit counters, over all cloud points (held-out included): rms = RMS f / c,
// dist_mm = RMS |f| / |grad f| in mm, sign = fraction of p +/- eps n with the
// right sign, sign2mm = the same at p +/- 2 mm n; active = control points,
// iters = CG iterations. Parts counters: mean control points per part
// and the HoCP error of capping (mean squared distance to the uncapped
// histogram).
//
// Run: build-*/bin/bench_ibs [--benchmark_filter=...]

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/dataset/bop_dataset.h"
#include "core/features/depth_cloud.h"
#include "core/features/hocp.h"
#include "core/features/part_extractor.h"
#include "core/features/unit_cube_frame.h"
#include "core/ibs/ibs_fitter.h"
#include "core/ibs/ibs_quality.h"
#include "core/render/depth_renderer.h"

#ifndef IHF_SHARED_DIR
#define IHF_SHARED_DIR "../shared"
#endif

namespace ihf {
namespace {

[[noreturn]] void die(const std::string &what)
{
	std::fprintf(stderr, "bench_ibs: %s\n", what.c_str());
	std::exit(1);
}

// A cloud in camera mm and in the unit cube (s = 1).
struct View {
	std::string name;
	CameraIntrinsics intrinsics;
	std::vector<CloudPoint> cloud;
	UnitCubeFrame frame;
	std::vector<Eigen::Vector3f> unit, normals;
};

View makeView(const std::string &name, const DepthImageMm &depth, const CameraIntrinsics &k,
	      PixelBox box)
{
	View v;
	v.name = name;
	v.intrinsics = k;
	v.cloud.resize(static_cast<size_t>(box.w) * box.h);
	auto n = cloudFromDepth(depth.view(), k, box, DepthCloudConfig{}, v.cloud);
	if (!n)
		die(name + ": " + n.error().message);
	v.cloud.resize(*n);
	auto f = makeUnitCubeFrame(v.cloud);
	if (!f)
		die(name + ": " + f.error().message);
	v.frame = *f;
	v.unit.resize(v.cloud.size());
	v.normals.resize(v.cloud.size());
	toUnitCube(v.cloud, v.frame, v.unit, v.normals);
	return v;
}

View sphereView(const CameraIntrinsics &k)
{
	DepthImageMm depth(k.width, k.height, 0.0f);
	const Eigen::Vector3d c(0, 0, 750);
	const double radius = 60;
	for (int v = 0; v < k.height; ++v)
		for (int u = 0; u < k.width; ++u) {
			const Eigen::Vector3d r((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
			const double a = r.squaredNorm(), b = -2.0 * r.dot(c);
			const double disc = b * b - 4 * a * (c.squaredNorm() - radius * radius);
			if (disc >= 0)
				depth.at(u, v) = static_cast<float>((-b - std::sqrt(disc)) / (2 * a));
		}
	const Eigen::Vector2d px = k.project(c);
	const int half = static_cast<int>(radius * k.fx / 750.0) + 4;
	return makeView("sphere", depth, k,
			{static_cast<int>(px.x()) - half, static_cast<int>(px.y()) - half, 2 * half, 2 * half});
}

const std::vector<View> &views()
{
	static const std::vector<View> all = [] {
		auto ds = BopDataset::open(std::filesystem::path(IHF_SHARED_DIR) / "data/lmo", "test");
		if (!ds)
			die(ds.error().message);
		const CameraIntrinsics k = ds->camera().intrinsics;
		auto scene = ds->loadScene(2);
		if (!scene)
			die(scene.error().message);
		const auto &gt = scene->gt.at(3);
		const auto &info = scene->gtInfo.at(3);
		size_t idx = 0;
		while (idx < gt.size() && gt[idx].objId != 8)
			++idx;
		if (idx == gt.size())
			die("driller (obj 8) not in scene 2 image 3");
		const auto &b = info[idx].bboxObj;
		const PixelBox box{b[0], b[1], b[2], b[3]};

		std::vector<View> v;
		v.push_back(sphereView(k));

		auto mesh = ds->loadModel(8);
		if (!mesh)
			die(mesh.error().message);
		DepthImageMm rendered(k.width, k.height, 0.0f);
		DepthRenderer renderer(mesh->vertices.size());
		auto st = renderer.render(*mesh, gt[idx].pose, k, rendered.view());
		if (!st)
			die(st.error().message);
		v.push_back(makeView("render", rendered, k, box));

		auto depth = ds->loadDepthMm(2, 3, ds->camera().depthScale);
		if (!depth)
			die(depth.error().message);
		v.push_back(makeView("real", *depth, k, box));
		for (const View &x : v)
			std::fprintf(stderr, "bench_ibs: view %s: %zu points, alpha %.1f mm, h %.3f\n",
				     x.name.c_str(), x.cloud.size(), x.frame.alpha, depthExtent(x.unit));
		return v;
	}();
	return all;
}

enum SolverVariant { kCg, kCgWarm, kMba, kBa1, kVariants };
const char *kVariantNames[] = {"cg30", "cg30+mba3", "mba3", "ba1"};

IbsConfig solverConfig(int variant, int n)
{
	IbsConfig cfg;
	cfg.n = n;
	cfg.maxPoints = 2000;
	switch (variant) {
	case kCg:
		cfg.warmStart = IbsWarmStart::kZero;
		break;
	case kCgWarm:
		cfg.warmStart = IbsWarmStart::kMultilevelBa;
		break;
	case kMba:
		cfg.solver = IbsSolver::kMultilevelBa;
		break;
	case kBa1:
		cfg.solver = IbsSolver::kMultilevelBa;
		cfg.mbaLevels = 1;
		break;
	}
	return cfg;
}

IbsLimits benchLimits()
{
	return IbsLimits{100, 4000, 150000};
}

// Args: view, solver variant, N.
void BM_Fit(benchmark::State &state)
{
	const View &v = views()[state.range(0)];
	const IbsConfig cfg = solverConfig(static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
	IbsFitter fitter(benchLimits());
	std::vector<ControlPoint> cps(benchLimits().maxActive);
	IbsFitStats stats;
	for (auto _ : state) {
		auto s = fitter.fit(v.unit, v.normals, cfg, cps);
		if (!s) {
			state.SkipWithError(s.error().message.c_str());
			return;
		}
		stats = *s;
		benchmark::DoNotOptimize(cps.data());
	}
	const IbsFitQuality q = measureFitQuality(fitter, v.unit, v.normals, cfg);
	// Distances in mm and a sign probe at +-2 mm compare lattices fairly.
	const float mm = v.frame.mmPerUnit();
	const IbsFitQuality q2 = measureFitQuality(fitter, v.unit, v.normals, cfg,
						   2.0f / (mm * fitter.lattice().delta()));
	state.counters["rms"] = q.rmsAtData;
	state.counters["sign"] = q.signCorrect;
	state.counters["dist_mm"] = q.rmsDistance * mm;
	state.counters["sign2mm"] = q2.signCorrect;
	state.counters["active"] = stats.activeCount;
	state.counters["reservedMB"] = fitter.reservedBytes() / 1e6;
	state.counters["iters"] = stats.iterations;
	state.SetLabel(v.name + "/" + kVariantNames[state.range(1)] + "/N" + std::to_string(cfg.n));
}
BENCHMARK(BM_Fit)
	->ArgsProduct({{0, 1, 2}, {kCg, kCgWarm, kMba, kBa1}, {50, 80, 100}})
	->Unit(benchmark::kMillisecond);

// Args: view, threads. The default fit (CG, N = 50) with its products
// spread over a pool, as the estimator runs it.
void BM_FitThreads(benchmark::State &state)
{
	const View &v = views()[state.range(0)];
	const int threads = static_cast<int>(state.range(1));
	const IbsConfig cfg = solverConfig(kCg, 50);
	IbsLimits limits = benchLimits();
	limits.threads = threads;
	WorkerPool pool(threads);
	IbsFitter fitter(limits);
	std::vector<ControlPoint> cps(limits.maxActive);
	IbsFitStats stats;
	for (auto _ : state) {
		auto s = fitter.fit(v.unit, v.normals, cfg, cps, {}, &pool);
		if (!s) {
			state.SkipWithError(s.error().message.c_str());
			return;
		}
		stats = *s;
		benchmark::DoNotOptimize(cps.data());
	}
	state.counters["active"] = stats.activeCount;
	state.counters["constraints"] = stats.constraints;
	state.counters["iters"] = stats.iterations;
	state.SetLabel(v.name + "/threads" + std::to_string(threads));
}
BENCHMARK(BM_FitThreads)->ArgsProduct({{0, 1, 2}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

// A fitted view with its parts, shared by the part and HoCP benchmarks.
struct Fitted {
	std::vector<ControlPoint> cps;
	int active = 0;
	float delta = 0;
};

const Fitted &fitted(int view, int n)
{
	static std::map<std::pair<int, int>, Fitted> cache;
	auto it = cache.find({view, n});
	if (it != cache.end())
		return it->second;
	Fitted f;
	IbsFitter fitter(benchLimits());
	f.cps.resize(benchLimits().maxActive);
	auto s = fitter.fit(views()[view].unit, views()[view].normals, solverConfig(kCg, n), f.cps);
	if (!s)
		die(s.error().message);
	f.active = s->activeCount;
	f.delta = fitter.lattice().delta();
	return cache.emplace(std::make_pair(view, n), std::move(f)).first->second;
}

PartSource sourceOf(int view, const Fitted &f)
{
	const View &v = views()[view];
	return PartSource{v.cloud, v.unit, std::span<const ControlPoint>(f.cps.data(), f.active),
			  v.frame, v.intrinsics, f.delta};
}

// Args: view, part kind, N. Time per part extracted (stride 4).
void BM_ExtractParts(benchmark::State &state)
{
	const int view = static_cast<int>(state.range(0));
	const Fitted &f = fitted(view, static_cast<int>(state.range(2)));
	PartConfig cfg;
	cfg.kind = state.range(1) ? PartKind::kFixed : PartKind::kVariable;
	PartExtractor ex(PartLimits{20000, 150000, 640 * 480});
	std::vector<Part> parts(5000);
	std::vector<PartCp> pool(parts.size() * cfg.maxControlPoints);
	int count = 0;
	double cpTotal = 0;
	for (auto _ : state) {
		if (!ex.prepare(sourceOf(view, f))) {
			state.SkipWithError("prepare failed");
			return;
		}
		auto n = ex.extractAll(cfg, HocpConfig{}, parts, pool);
		if (!n) {
			state.SkipWithError(n.error().message.c_str());
			return;
		}
		count = *n;
	}
	// Outside the timing: how many control points the regions hold before
	// the cap (the timed scan stops at the cap).
	cfg.countAllControlPoints = true;
	if (ex.extractAll(cfg, HocpConfig{}, parts, pool))
		for (int i = 0; i < count; ++i)
			cpTotal += parts[i].cpTotal;
	state.counters["parts"] = count;
	state.counters["cpBeforeCap"] = count ? cpTotal / count : 0;
	// Seconds per part (shown with an SI prefix, u = microseconds).
	state.counters["perPart"] = benchmark::Counter(static_cast<double>(count) * state.iterations(),
						       benchmark::Counter::kIsRate |
							       benchmark::Counter::kInvert);
	state.SetLabel(views()[view].name + (state.range(1) ? "/fixed" : "/variable") + "/N" +
		       std::to_string(state.range(2)));
}
BENCHMARK(BM_ExtractParts)
	->ArgsProduct({{2}, {0, 1}, {50, 100}})
	->Unit(benchmark::kMillisecond);

// Parts of the real view at N = 100 (variable, cap 256) for HoCP timing.
struct PartSet {
	std::vector<Part> parts;
	std::vector<PartCp> pool;
};

const PartSet &realParts(int cap, PartCap mode)
{
	static std::map<std::pair<int, int>, PartSet> cache;
	auto key = std::make_pair(cap, static_cast<int>(mode));
	auto it = cache.find(key);
	if (it != cache.end())
		return it->second;
	PartSet s;
	PartConfig cfg;
	cfg.maxControlPoints = cap;
	cfg.cap = mode;
	PartExtractor ex(PartLimits{20000, 150000, 640 * 480});
	if (!ex.prepare(sourceOf(2, fitted(2, 100))))
		die("prepare failed");
	s.parts.resize(5000);
	s.pool.resize(s.parts.size() * static_cast<size_t>(cap));
	auto n = ex.extractAll(cfg, HocpConfig{}, s.parts, s.pool);
	if (!n)
		die(n.error().message);
	s.parts.resize(*n);
	return cache.emplace(key, std::move(s)).first->second;
}

// Args: variant (0 keyed, 1 depth-checked, 2 reference formulas). Per part.
void BM_Hocp(benchmark::State &state)
{
	const PartSet &s = realParts(256, PartCap::kUniform);
	const HocpConfig cfg;
	std::vector<float> h(hocpDimension(cfg));
	size_t i = 0;
	double cps = 0;
	for (const Part &p : s.parts)
		cps += p.cpCount;
	for (auto _ : state) {
		const Part &p = s.parts[i];
		std::span<const PartCp> c(s.pool.data() + p.cpOffset, p.cpCount);
		const Part &t = s.parts[(i * 7 + 3) % s.parts.size()];
		switch (state.range(0)) {
		case 0:
			computeHocp(c, cfg, h);
			break;
		case 1:
			computeHocpDepthChecked(c, t.zMin, t.zMax, 0.02f, cfg, h);
			break;
		default:
			computeHocpReference(c, cfg, h);
			break;
		}
		benchmark::DoNotOptimize(h.data());
		i = (i + 1) % s.parts.size();
	}
	state.counters["cpPerPart"] = cps / s.parts.size();
	static const char *names[] = {"keyed", "depth-checked", "reference"};
	state.SetLabel(names[state.range(0)]);
}
BENCHMARK(BM_Hocp)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

// HoCP error of capping: mean squared distance between the capped and the
// uncapped histogram of the same part. Args: cap mode, cap.
void BM_CapError(benchmark::State &state)
{
	const PartCap mode = state.range(0) ? PartCap::kLargestWeight : PartCap::kUniform;
	const int cap = static_cast<int>(state.range(1));
	const PartSet &full = realParts(100000, PartCap::kUniform);
	const PartSet &capped = realParts(cap, mode);
	const HocpConfig cfg;
	std::vector<float> a(hocpDimension(cfg)), b(a.size());
	double err = 0;
	for (auto _ : state) {
		err = 0;
		for (size_t i = 0; i < full.parts.size(); ++i) {
			const Part &p = full.parts[i], &q = capped.parts[i];
			computeHocp(std::span<const PartCp>(full.pool.data() + p.cpOffset, p.cpCount), cfg, a);
			computeHocp(std::span<const PartCp>(capped.pool.data() + q.cpOffset, q.cpCount), cfg, b);
			err += hocpDistanceSquared(a, b);
		}
		err /= full.parts.size();
	}
	// For scale: the mean squared distance between the uncapped histograms
	// of successive parts (neighbours on the centre grid).
	double neighbour = 0;
	for (size_t i = 1; i < full.parts.size(); ++i) {
		const Part &p = full.parts[i - 1], &q = full.parts[i];
		computeHocp(std::span<const PartCp>(full.pool.data() + p.cpOffset, p.cpCount), cfg, a);
		computeHocp(std::span<const PartCp>(full.pool.data() + q.cpOffset, q.cpCount), cfg, b);
		neighbour += hocpDistanceSquared(a, b);
	}
	state.counters["hocpErr"] = err;
	state.counters["neighbourDist"] = neighbour / std::max<size_t>(full.parts.size() - 1, 1);
	state.SetLabel(std::string(state.range(0) ? "largest-weight" : "uniform") + "/cap" +
		       std::to_string(cap));
}
BENCHMARK(BM_CapError)
	->ArgsProduct({{0, 1}, {64, 128, 256, 512}})
	->Iterations(1)
	->Unit(benchmark::kMillisecond);

} // namespace
} // namespace ihf
