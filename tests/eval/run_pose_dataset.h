// SPDX-License-Identifier: MIT
#pragma once

// A small BOP dataset made by the tests of `ihf eval --run-poses`: scene 7
// of split "test" with images 4, 5 and 9 (64 x 48; the depth of image k is
// 1000 + k everywhere, so a recorded frame tells which image it came from),
// and two objects, both a 60 x 40 x 20 mm box centred on its origin:
// object 1 plain (ADD), object 2 with a half-turn symmetry about z (ADI).
//
//   image 4: object 1 at truthPose(4)
//   image 5: object 1 twice, at truthPose(5) and 200 mm to its right
//   image 9: object 2 at truthPose(9)
//
// With `secondScene`, scene 8 (image 0, no ground truth) is added.

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/geometry/ply_loader.h"

namespace ihf::test {

inline constexpr int kRunPoseScene = 7;
inline const double kBoxDiameter = std::sqrt(60.0 * 60.0 + 40.0 * 40.0 + 20.0 * 20.0);

inline Pose truthPose(int imageId)
{
	Pose p;
	p.R = Eigen::AngleAxisd(0.1 * imageId, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
	p.t = {10.0 * imageId, -5.0 * imageId, 700.0 + 10.0 * imageId};
	return p;
}

inline Mesh boxMesh()
{
	Mesh m;
	for (float x : {-30.f, 30.f})
		for (float y : {-20.f, 20.f})
			for (float z : {-10.f, 10.f})
				m.vertices.push_back({x, y, z});
	// Corner i has x = bit 2, y = bit 1, z = bit 0; two triangles per side.
	m.faces = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
		   {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
	return m;
}

inline void makeRunPoseDataset(const std::filesystem::path &root, bool secondScene = false)
{
	BopCamera cam;
	cam.intrinsics = CameraIntrinsics{500, 501, 31.5, 23.5, 64, 48};
	std::map<int, ModelInfo> info;
	for (int id : {1, 2}) {
		ModelInfo &m = info[id];
		m.objId = id;
		m.diameter = kBoxDiameter;
		m.min = {-30, -20, -10};
		m.size = {60, 40, 20};
	}
	Pose halfTurn;
	halfTurn.R = Eigen::Vector3d(-1, -1, 1).asDiagonal();
	info[2].symmetriesDiscrete.push_back(halfTurn);
	ASSERT_TRUE(createBopDataset(root, cam, info).ok());
	auto ds = BopDataset::open(root);
	ASSERT_TRUE(ds.ok()) << ds.error().message;
	for (int id : {1, 2})
		ASSERT_TRUE(savePly(ds->modelPath(id), boxMesh()).ok());

	BopScene scene;
	scene.sceneId = kRunPoseScene;
	for (int im : {4, 5, 9}) {
		SceneCamera sc;
		sc.intrinsics = cam.intrinsics;
		scene.cameras[im] = sc;
		ASSERT_TRUE(writeDepthPng(ds->depthPath(kRunPoseScene, im),
					  DepthImage16(64, 48, static_cast<uint16_t>(1000 + im)))
				    .ok());
	}
	Pose right = truthPose(5);
	right.t.x() += 200;
	scene.gt[4] = {{1, truthPose(4)}};
	scene.gt[5] = {{1, truthPose(5)}, {1, right}};
	scene.gt[9] = {{2, truthPose(9)}};
	ASSERT_TRUE(ds->saveScene(scene).ok());

	if (secondScene) {
		BopScene other;
		other.sceneId = kRunPoseScene + 1;
		other.cameras[0] = scene.cameras[4];
		other.gt[0] = {};
		ASSERT_TRUE(ds->saveScene(other).ok());
	}
}

} // namespace ihf::test
