// SPDX-License-Identifier: MIT
// Where a nearly symmetric object's small part shows (the split by
// visibility): for every ground-truth instance of a BOP dataset whose object
// has a body mesh (the object without its part: `ihf synth --make-object
// NAME --without-part`) in BODIES, the object and its body are rendered at
// the true pose; the part's pixels are those where the object is drawn in
// front of its body (or the body not at all), and of them the visible ones
// those where the scene's depth lies within 10 mm of the object's render.
// Whether the depth can tell the truth from its rivals: the true pose is
// turned about each of the object's near-symmetries (found as training
// finds them; every 15 deg about a continuous axis, both ways round about a
// discrete one), and for each turn that the evaluation counts as another
// pose (its model points lie more than 0.1 diameters away) the pixels where
// the two renders differ and the sensor sees (the scene's depth there is
// not in front of both by more than 10 mm) are counted; rival_px is the
// fewest over the turns (-1: no such turn). Few such pixels: no depth can
// tell the two apart.
// One JSON line per instance: scene_id, im_id, obj_id, part_px, visible_px,
// rival_px.
//
//   part_visibility DATASET BODIES OUT.jsonl

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "core/dataset/bop_dataset.h"
#include "core/geometry/ply_loader.h"
#include "core/pose/half_turns.h"
#include "core/render/depth_renderer.h"
#include "core/runtime/arena.h"
#include "core/training/near_symmetry_finder.h"

namespace fs = std::filesystem;
using namespace ihf;

namespace {

constexpr float kToleranceMm = 10.0f;

// The true pose's rivals: turned about each near-symmetry, as the estimator
// turns a pose (core/estimation/symmetry_rivals.cpp), those the evaluation
// counts as other poses.
std::vector<Pose> rivalsOf(const Pose &truth, const Mesh &mesh, const std::vector<NearSymmetry> &symmetries)
{
	const double diameter = meshDiameter(mesh);
	std::vector<Pose> out;
	auto add = [&](const NearSymmetry &s, double deg) {
		const Eigen::Matrix3d turn =
			Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, s.axis.cast<double>()).toRotationMatrix();
		const Eigen::Vector3d c = s.point.cast<double>();
		double moved = 0;
		for (const Eigen::Vector3f &v : mesh.vertices)
			moved += (turn * (v.cast<double>() - c) + c - v.cast<double>()).norm();
		if (moved / static_cast<double>(std::max<size_t>(mesh.vertices.size(), 1)) <= 0.1 * diameter)
			return;
		out.push_back(turnedAbout(truth, turn, c));
	};
	for (const NearSymmetry &s : symmetries) {
		if (s.continuous()) {
			for (int k = 1; k < 24; ++k)
				add(s, 15.0 * k);
		} else {
			add(s, s.turnDeg);
			if (std::abs(s.turnDeg - 180.0f) > 1e-3f)
				add(s, -s.turnDeg);
		}
	}
	return out;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 4) {
		std::fprintf(stderr, "usage: part_visibility DATASET BODIES OUT.jsonl\n");
		return 2;
	}
	auto ds = BopDataset::open(argv[1]);
	if (!ds) {
		std::fprintf(stderr, "part_visibility: %s\n", ds.error().message.c_str());
		return 1;
	}
	std::FILE *out = std::fopen(argv[3], "w");
	if (!out)
		return 1;
	constexpr size_t kMaxVertices = 200000;
	auto arena = Arena::create(DepthRenderer::arenaBytes(kMaxVertices));
	if (!arena)
		return 1;
	DepthRenderer renderer;
	if (!renderer.reserve(kMaxVertices, *arena).ok())
		return 1;
	std::map<int, std::vector<NearSymmetry>> symmetries;
	for (int sceneId : ds->sceneIds()) {
		auto scene = ds->loadScene(sceneId);
		if (!scene) {
			std::fprintf(stderr, "part_visibility: %s\n", scene.error().message.c_str());
			return 1;
		}
		for (const auto &[imId, instances] : scene->gt) {
			const SceneCamera &cam = scene->cameras.at(imId);
			auto depth = ds->loadDepthMm(sceneId, imId, cam.depthScale);
			if (!depth)
				return 1;
			const CameraIntrinsics &K = cam.intrinsics;
			for (const GtInstance &g : instances) {
				char name[32];
				std::snprintf(name, sizeof(name), "obj_%06d.ply", g.objId);
				const fs::path bodyPath = fs::path(argv[2]) / name;
				if (!fs::exists(bodyPath))
					continue;
				auto whole = ds->loadModel(g.objId);
				auto body = loadPly(bodyPath);
				if (!whole || !body)
					return 1;
				DepthImageMm a(K.width, K.height, 0.0f), b(K.width, K.height, 0.0f);
				if (!renderer.render(*whole, g.pose, K, a.view()) || !renderer.render(*body, g.pose, K, b.view()))
					return 1;
				int partPx = 0, visiblePx = 0;
				for (int y = 0; y < K.height; ++y)
					for (int x = 0; x < K.width; ++x) {
						const float za = a.at(x, y), zb = b.at(x, y);
						if (!(za > 0) || (zb > 0 && za >= zb - 2.0f))
							continue;
						++partPx;
						const float o = depth->at(x, y);
						visiblePx += o > 0 && std::abs(o - za) <= kToleranceMm;
					}
				if (!symmetries.count(g.objId))
					symmetries[g.objId] = findNearSymmetries(*whole);
				int rivalPx = -1;
				for (const Pose &rival : rivalsOf(g.pose, *whole, symmetries[g.objId])) {
					DepthImageMm r(K.width, K.height, 0.0f);
					if (!renderer.render(*whole, rival, K, r.view()))
						return 1;
					int seen = 0;
					for (int y = 0; y < K.height; ++y)
						for (int x = 0; x < K.width; ++x) {
							const float za = a.at(x, y), zr = r.at(x, y);
							const bool da = za > 0, dr = zr > 0;
							if (da == dr && (!da || std::abs(za - zr) <= kToleranceMm))
								continue;
							const float o = depth->at(x, y);
							const float front = da && dr ? std::min(za, zr) : (da ? za : zr);
							seen += o > 0 && o >= front - kToleranceMm;
						}
					rivalPx = rivalPx < 0 ? seen : std::min(rivalPx, seen);
				}
				std::fprintf(out,
					     "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"part_px\":%d,\"visible_px\":%d,"
					     "\"rival_px\":%d}\n",
					     sceneId, imId, g.objId, partPx, visiblePx, rivalPx);
			}
		}
	}
	std::fclose(out);
	return 0;
}
