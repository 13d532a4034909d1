// SPDX-License-Identifier: MIT
#include "benchmarks/peers/peer_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "benchmarks/peers/model_sampler.h"
#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/features/depth_cloud.h"

namespace ihf::peers {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0)
{
	return std::chrono::duration<double>(Clock::now() - t0).count();
}

double percentile(std::vector<double> v, double p)
{
	if (v.empty())
		return -1;
	std::sort(v.begin(), v.end());
	size_t k = static_cast<size_t>(std::ceil(p * static_cast<double>(v.size())));
	return v[std::clamp<size_t>(k, 1, v.size()) - 1];
}

std::string statsJson(const char *peer, const PeerRunSummary &s)
{
	nlohmann::ordered_json j;
	j["peer"] = peer;
	j["box_ms"] = {{"count", s.boxSeconds.size()},
		       {"p50", 1e3 * percentile(s.boxSeconds, 0.5)},
		       {"p90", 1e3 * percentile(s.boxSeconds, 0.9)},
		       {"p99", 1e3 * percentile(s.boxSeconds, 0.99)},
		       {"max", 1e3 * percentile(s.boxSeconds, 1.0)}};
	nlohmann::ordered_json prep = nlohmann::ordered_json::object();
	double total = 0;
	for (auto [id, sec] : s.prepSeconds) {
		prep[std::to_string(id)] = sec;
		total += sec;
	}
	j["prep_s"] = prep;
	j["prep_s_total"] = total;
	j["boxes"] = s.boxes;
	j["poses"] = s.poses;
	j["skipped"] = s.skipped;
	return j.dump(2) + "\n";
}

} // namespace

Expected<PeerRunSummary> runPeer(Peer &peer, const PeerRunOptions &o)
{
	auto dataset = BopDataset::open(o.dataset, o.split);
	if (!dataset)
		return dataset.error();
	auto dets = readDetections(o.boxes);
	if (!dets)
		return dets.error();

	std::set<int> wanted(o.objects.begin(), o.objects.end());
	std::map<std::pair<int, int>, std::vector<const Detection *>> perImage;
	std::set<int> objIds;
	for (const Detection &d : *dets) {
		if (!wanted.empty() && !wanted.count(d.categoryId))
			continue;
		perImage[{d.sceneId, d.imageId}].push_back(&d);
		objIds.insert(d.categoryId);
	}

	PeerRunSummary summary;
	// Model preparation, timed apart from the boxes: sampling the mesh is
	// shared input, the peer's own training is its preparation time.
	for (int id : objIds) {
		auto mesh = dataset->loadModel(id);
		if (!mesh)
			return mesh.error();
		auto infoIt = dataset->modelsInfo().find(id);
		double diameter = infoIt != dataset->modelsInfo().end() ? infoIt->second.diameter : 0;
		auto model = sampleModel(*mesh, id, diameter, o.modelPoints, o.seed + id);
		if (!model)
			return model.error();
		auto t0 = Clock::now();
		if (Status st = peer.prepare(*model); !st)
			return Error{st.error().code, std::string(peer.name()) + ": object " +
							      std::to_string(id) + ": " + st.error().message};
		summary.prepSeconds.emplace_back(id, secondsSince(t0));
		if (!o.quiet)
			std::fprintf(stderr, "ihf_peers %s: object %d prepared in %.3f s (%zu model points, diameter %.1f mm)\n",
				     peer.name(), id, summary.prepSeconds.back().second, model->points.size(),
				     model->diameter);
	}

	std::map<int, BopScene> scenes;
	std::vector<ResultRow> rows;
	const DepthCloudConfig cloudCfg;
	std::vector<CloudPoint> cloud;
	std::vector<CloudPoint> withNormals;
	for (const auto &[key, boxes] : perImage) {
		auto [sceneId, imId] = key;
		if (!scenes.count(sceneId)) {
			auto scene = dataset->loadScene(sceneId);
			if (!scene)
				return scene.error();
			scenes[sceneId] = std::move(scene.value());
		}
		const BopScene &scene = scenes[sceneId];
		auto camIt = scene.cameras.find(imId);
		if (camIt == scene.cameras.end()) {
			std::fprintf(stderr, "ihf_peers: scene %d image %d: not in scene_camera.json; boxes skipped\n",
				     sceneId, imId);
			summary.skipped += static_cast<int>(boxes.size());
			continue;
		}
		auto depth = dataset->loadDepthMm(sceneId, imId, camIt->second.depthScale);
		if (!depth) {
			std::fprintf(stderr, "ihf_peers: %s; frame skipped\n", depth.error().message.c_str());
			summary.skipped += static_cast<int>(boxes.size());
			continue;
		}
		CameraIntrinsics K = camIt->second.intrinsics;
		K.width = depth->width();
		K.height = depth->height();
		cloud.resize(static_cast<size_t>(K.width) * K.height);

		std::vector<ResultRow> imageRows;
		double imageTime = 0;
		for (const Detection *d : boxes) {
			const PixelBox box = pixelsOfBox(d->bbox);
			// The crop is part of the box's time, as it is for `ihf estimate`.
			auto t0 = Clock::now();
			auto n = cloudFromDepth(depth->view(), K, box, cloudCfg, cloud);
			PeerEstimate e;
			if (!n) {
				e.reason = n.error().message;
			} else {
				withNormals.clear();
				for (int i = 0; i < *n; ++i)
					if (cloud[i].hasNormal())
						withNormals.push_back(cloud[i]);
				e = peer.estimate(d->categoryId, withNormals);
			}
			double dt = secondsSince(t0);
			summary.boxSeconds.push_back(dt);
			imageTime += dt;
			++summary.boxes;
			if (!e.found) {
				if (!o.quiet)
					std::fprintf(stderr, "ihf_peers %s: scene %d image %d object %d: no pose: %s\n",
						     peer.name(), sceneId, imId, d->categoryId, e.reason.c_str());
				continue;
			}
			ResultRow r;
			r.sceneId = sceneId;
			r.imId = imId;
			r.objId = d->categoryId;
			r.score = e.score;
			r.pose = e.pose;
			imageRows.push_back(r);
		}
		for (ResultRow &r : imageRows) {
			r.time = imageTime;
			rows.push_back(r);
		}
	}
	summary.poses = static_cast<int>(rows.size());
	if (Status st = writeResultsCsv(o.out, rows); !st)
		return st.error();
	if (!o.statsJson.empty())
		if (Status st = writeFileAtomic(o.statsJson, statsJson(peer.name(), summary)); !st)
			return st.error();
	std::fprintf(stderr,
		     "ihf_peers %s: %d boxes, %d poses, %d skipped; per box median %.1f ms, p99 %.1f ms; "
		     "wrote %s\n",
		     peer.name(), summary.boxes, summary.poses, summary.skipped,
		     1e3 * percentile(summary.boxSeconds, 0.5), 1e3 * percentile(summary.boxSeconds, 0.99),
		     o.out.c_str());
	return summary;
}

} // namespace ihf::peers
