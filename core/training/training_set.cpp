// SPDX-License-Identifier: MIT
#include "core/training/training_set.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "core/features/depth_cloud.h"
#include "core/features/hocp.h"
#include "core/features/part_extractor.h"
#include "core/features/unit_cube_frame.h"
#include "core/ibs/ibs_fitter.h"
#include "core/render/depth_renderer.h"

namespace ihf {

namespace {

struct ViewResult {
	std::vector<PartCp> pool;
	std::vector<TrainingSample> samples;
	std::vector<float> histograms;
	std::vector<Vote> labels;
	bool skipped = false;
};

// One worker's tools, sized once.
class ViewWorker
{
public:
	ViewWorker(const Mesh &mesh, const CameraIntrinsics &k, const ModelParams &params)
		: mesh_(mesh), k_(k), params_(params), renderer_(mesh.vertices.size()),
		  depth_(k.width, k.height, 0.0f)
	{
		IbsLimits ibsLimits;
		ibsLimits.maxN = std::max(params.ibs.n, 4);
		ibsLimits.maxPoints = std::max(params.ibs.maxPoints, 16);
		ibsLimits.maxActive = 200000;
		fitter_.reserve(ibsLimits);
		PartLimits partLimits;
		partLimits.maxPoints = k.width * k.height;
		partLimits.maxControlPoints = ibsLimits.maxActive;
		partLimits.maxBoxPixels = k.width * k.height;
		extractor_.reserve(partLimits);
		cloud_.resize(static_cast<size_t>(k.width) * k.height);
		unit_.resize(cloud_.size());
		normals_.resize(cloud_.size());
		active_.resize(ibsLimits.maxActive);
		partCps_.resize(std::max(params.parts.maxControlPoints, 1));
		centres_.resize(cloud_.size());
	}

	Expected<ViewResult> run(const TrainingView &view, const TrainingSetConfig &cfg, uint64_t seed)
	{
		ViewResult out;
		const int dims = hocpDimension(params_.hocp);
		depth_.view().fill(0.0f);
		auto rs = renderer_.render(mesh_, view.pose, k_, depth_.view());
		if (!rs)
			return rs.error();

		// Silhouette box of the render.
		int x0 = k_.width, y0 = k_.height, x1 = -1, y1 = -1;
		for (int y = 0; y < k_.height; ++y)
			for (int x = 0; x < k_.width; ++x)
				if (depth_.at(x, y) > 0) {
					x0 = std::min(x0, x);
					x1 = std::max(x1, x);
					y0 = std::min(y0, y);
					y1 = std::max(y1, y);
				}
		if (x1 < 0) {
			out.skipped = true;
			return out;
		}
		PixelBox box{x0, y0, x1 - x0 + 1, y1 - y0 + 1};
		auto n = cloudFromDepth(depth_.view(), k_, box, params_.cloud, cloud_);
		if (!n)
			return n.error();
		std::span<const CloudPoint> cloud(cloud_.data(), *n);
		if (cloud.size() < 32) {
			out.skipped = true;
			return out;
		}

		std::mt19937_64 rng(seed);
		auto uniform01 = [&rng] { return static_cast<float>(rng() >> 40) * 0x1.0p-24f; };
		const Eigen::Quaternionf rotation(view.pose.R.cast<float>());
		const Eigen::Vector3f origin = view.pose.t.cast<float>();
		std::vector<float> hist(dims);

		// Frames of the whole silhouette, before any occlusion.
		std::vector<UnitCubeFrame> frames;
		for (float s : cfg.scales) {
			auto frame = makeUnitCubeFrame(cloud, s);
			if (!frame)
				return frame.error();
			frames.push_back(*frame);
		}
		if (cfg.occludedViews > 0 && uniform01() < cfg.occludedViews) {
			const float fraction = cfg.occlusionMin + uniform01() * (cfg.occlusionMax - cfg.occlusionMin);
			occlude(box, fraction, uniform01() * 2.0f * static_cast<float>(M_PI));
			auto m = cloudFromDepth(depth_.view(), k_, box, params_.cloud, cloud_);
			if (!m)
				return m.error();
			cloud = std::span<const CloudPoint>(cloud_.data(), *m);
			if (cloud.size() < 32) {
				out.skipped = true;
				return out;
			}
		}

		for (const UnitCubeFrame &f : frames) {
			const UnitCubeFrame *frame = &f;
			toUnitCube(cloud, *frame, std::span(unit_.data(), cloud.size()),
				   std::span(normals_.data(), cloud.size()));
			auto fit = fitter_.fit(std::span(unit_.data(), cloud.size()),
					       std::span(normals_.data(), cloud.size()), params_.ibs,
					       active_);
			if (!fit)
				return fit.error();
			PartSource src;
			src.cloud = cloud;
			src.unit = std::span(unit_.data(), cloud.size());
			src.cps = std::span(active_.data(), fit->activeCount);
			src.frame = *frame;
			src.intrinsics = k_;
			src.latticeDelta = fitter_.lattice().delta();
			if (auto st = extractor_.prepare(src); !st)
				return st.error();
			int nc = extractor_.centres(params_.parts, centres_);
			if (nc <= 0)
				continue;
			// Draw partsPerImage distinct centres (partial Fisher-Yates).
			int want = std::min(nc, cfg.partsPerImage);
			for (int i = 0; i < want; ++i)
				std::swap(centres_[i], centres_[i + static_cast<int>(rng() % (nc - i))]);
			for (int i = 0; i < want; ++i) {
				auto part = extractor_.extract(centres_[i], params_.parts, params_.hocp,
							       partCps_);
				if (!part)
					return part.error();
				if (part->dataPoints < params_.parts.minDataPoints || part->cpCount == 0)
					continue;
				std::span<PartCp> cps(partCps_.data(), part->cpCount);
				float zMin = part->zMin, zMax = part->zMax;
				partToMillimetres(cps, zMin, zMax, frame->mmPerUnit(), params_.hocp);
				computeHocp(cps, params_.hocp, hist);

				TrainingSample sample;
				sample.cpOffset = static_cast<uint32_t>(out.pool.size());
				sample.cpCount = part->cpCount;
				sample.zMin = zMin;
				sample.zMax = zMax;
				out.pool.insert(out.pool.end(), cps.begin(), cps.end());
				out.samples.push_back(sample);
				out.histograms.insert(out.histograms.end(), hist.begin(), hist.end());
				out.labels.push_back({origin - part->centreCamera, rotation});
			}
		}
		return out;
	}

private:
	// Removes the silhouette pixels beyond a line of direction `angle`
	// placed so that about `fraction` of them go.
	void occlude(const PixelBox &box, float fraction, float angle)
	{
		const float c = std::cos(angle), s = std::sin(angle);
		std::vector<float> proj;
		for (int y = box.y; y < box.y + box.h; ++y)
			for (int x = box.x; x < box.x + box.w; ++x)
				if (depth_.at(x, y) > 0)
					proj.push_back(c * x + s * y);
		if (proj.empty())
			return;
		const size_t keep = std::min(proj.size() - 1,
					     static_cast<size_t>((1.0f - fraction) * static_cast<float>(proj.size())));
		std::nth_element(proj.begin(), proj.begin() + keep, proj.end());
		const float cut = proj[keep];
		for (int y = box.y; y < box.y + box.h; ++y)
			for (int x = box.x; x < box.x + box.w; ++x)
				if (c * x + s * y >= cut)
					depth_.at(x, y) = 0.0f;
	}

	const Mesh &mesh_;
	CameraIntrinsics k_;
	const ModelParams &params_;
	DepthRenderer renderer_;
	DepthImageMm depth_;
	IbsFitter fitter_;
	PartExtractor extractor_;
	std::vector<CloudPoint> cloud_;
	std::vector<Eigen::Vector3f> unit_, normals_;
	std::vector<ControlPoint> active_;
	std::vector<PartCp> partCps_;
	std::vector<int32_t> centres_;
};

} // namespace

Expected<TrainingSet> buildTrainingSet(const Mesh &mesh, const CameraIntrinsics &intrinsics,
				       const ModelParams &params, const TrainingSetConfig &config,
				       const ViewProgress &progress)
{
	if (mesh.vertices.empty() || mesh.faces.empty())
		return makeError(Errc::kInvalidArgument, "training: the mesh has no faces");
	if (!intrinsics.valid())
		return makeError(Errc::kInvalidArgument, "training: invalid camera intrinsics");
	for (float s : config.scales)
		if (!(s >= 1.0f))
			return makeError(Errc::kInvalidArgument,
					 "training: scale factors must be >= 1 (the unit cube holds the cloud at s = 1)");

	const auto views = sampleTrainingViews(config.views);
	std::vector<ViewResult> results(views.size());
	std::atomic<size_t> next{0};
	std::atomic<int> done{0};
	std::mutex errorMutex;
	std::optional<Error> firstError;

	auto work = [&] {
		ViewWorker worker(mesh, intrinsics, params);
		for (size_t i; (i = next++) < views.size();) {
			// Per-view seed: results do not depend on the thread count.
			uint64_t seed = config.seed * 0x9E3779B97F4A7C15ull + i * 0xBF58476D1CE4E5B9ull + 7;
			auto r = worker.run(views[i], config, seed);
			if (!r) {
				std::lock_guard lock(errorMutex);
				if (!firstError)
					firstError = r.error();
				return;
			}
			results[i] = std::move(r.value());
			int d = ++done;
			if (progress)
				progress(d, static_cast<int>(views.size()));
		}
	};
	const int threads = std::max(1, config.threads);
	std::vector<std::thread> pool;
	for (int t = 1; t < threads; ++t)
		pool.emplace_back(work);
	work();
	for (auto &t : pool)
		t.join();
	if (firstError)
		return *firstError;

	TrainingSet set;
	set.dims = hocpDimension(params.hocp);
	set.views = static_cast<int>(views.size());
	for (auto &r : results) {
		if (r.skipped) {
			set.skippedViews++;
			continue;
		}
		const uint32_t base = static_cast<uint32_t>(set.pool.size());
		for (auto s : r.samples) {
			s.cpOffset += base;
			set.samples.push_back(s);
		}
		set.pool.insert(set.pool.end(), r.pool.begin(), r.pool.end());
		set.histograms.insert(set.histograms.end(), r.histograms.begin(), r.histograms.end());
		set.labels.insert(set.labels.end(), r.labels.begin(), r.labels.end());
		r = ViewResult{};
	}
	if (set.samples.empty())
		return makeError(Errc::kInvalidArgument, "training: no view produced a part; is the mesh visible at the training distances?");
	return set;
}

} // namespace ihf
