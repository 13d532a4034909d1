// SPDX-License-Identifier: MIT
#pragma once

// Plain records of the BOP dataset format (https://bop.felk.cvut.cz format
// description): camera.json, models_info.json, scene_camera.json,
// scene_gt.json, scene_gt_info.json, results CSV and detection lists.

#include <array>
#include <map>
#include <optional>
#include <vector>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/pose.h"

namespace ihf {

// camera.json at the dataset root.
struct BopCamera {
	CameraIntrinsics intrinsics;
	double depthScale = 1.0; // raw depth * depthScale = millimetres
};

// One entry of symmetries_continuous: rotation about axis through offset (mm).
struct ContinuousSymmetry {
	Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
	Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

// One entry of models/models_info.json.
struct ModelInfo {
	int objId = 0;
	double diameter = 0; // mm
	Eigen::Vector3d min = Eigen::Vector3d::Zero();
	Eigen::Vector3d size = Eigen::Vector3d::Zero();
	std::vector<Pose> symmetriesDiscrete; // 4x4 row-major in the file
	bool hasContinuousSymmetry = false; // symmetries_continuous present
	std::vector<ContinuousSymmetry> symmetriesContinuous;
	// Evaluated with ADI (closest point) instead of ADD.
	bool symmetric() const { return hasContinuousSymmetry || !symmetriesDiscrete.empty(); }
};

// One image entry of scene_camera.json.
struct SceneCamera {
	CameraIntrinsics intrinsics; // cam_K; width/height from the image
	double depthScale = 1.0;
};

// One object instance of scene_gt.json.
struct GtInstance {
	int objId = 0;
	Pose pose;
};

// One object instance of scene_gt_info.json (boxes are x, y, w, h pixels).
struct GtInfo {
	std::array<int, 4> bboxObj{-1, -1, -1, -1};
	std::array<int, 4> bboxVisib{-1, -1, -1, -1};
	int pxCountAll = 0;
	int pxCountValid = 0; // -1: not in the file (optional: nothing here needs it)
	int pxCountVisib = 0;
	double visibFract = 0;
};

// One scene folder: SPLIT/SCENE/. Maps are keyed by image id.
struct BopScene {
	int sceneId = 0;
	std::map<int, SceneCamera> cameras;
	std::map<int, std::vector<GtInstance>> gt;
	std::map<int, std::vector<GtInfo>> gtInfo; // parallel to gt, may be empty
};

// One row of a BOP results CSV: scene_id,im_id,obj_id,score,R,t,time.
struct ResultRow {
	int sceneId = 0;
	int imId = 0;
	int objId = 0;
	double score = 0;
	Pose pose;
	double time = -1; // seconds for the whole image, -1 if unknown
};

// One given 2D box, as a BOP/COCO detection JSON entry.
struct Detection {
	int sceneId = 0;
	int imageId = 0;
	int categoryId = 0; // object id
	double score = 1.0;
	std::array<double, 4> bbox{0, 0, 0, 0}; // x, y, w, h
	double time = 0;
};

} // namespace ihf
