// SPDX-License-Identifier: MIT
// Where a nearly symmetric object's small part shows (the split by
// visibility): for every ground-truth instance of a BOP dataset whose object
// has a body mesh (the object without its part: `ihf synth --make-object
// NAME --without-part`) in BODIES, the object and its body are rendered at
// the true pose; the part's pixels are those where the object is drawn in
// front of its body (or the body not at all), and of them the visible ones
// those where the scene's depth lies within 10 mm of the object's render.
// One JSON line per instance: scene_id, im_id, obj_id, part_px, visible_px.
//
//   part_visibility DATASET BODIES OUT.jsonl

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/dataset/bop_dataset.h"
#include "core/geometry/ply_loader.h"
#include "core/render/depth_renderer.h"
#include "core/runtime/arena.h"

namespace fs = std::filesystem;
using namespace ihf;

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
						visiblePx += o > 0 && std::abs(o - za) <= 10.0f;
					}
				std::fprintf(out, "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"part_px\":%d,\"visible_px\":%d}\n",
					     sceneId, imId, g.objId, partPx, visiblePx);
			}
		}
	}
	std::fclose(out);
	return 0;
}
