// SPDX-License-Identifier: MIT
#pragma once

// A synthetic tabletop scene: the target resting on a table, clutter and
// occluders resting around it, the table slab, the floor and sometimes a wall,
// and a camera looking down at the target. World frame: the table top is the
// plane z = 0, +z up; lengths in millimetres.

#include <memory>
#include <vector>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"
#include "core/synth/model_library.h"
#include "core/synth/synth_random.h"
#include "core/synth/table_footprint.h"

namespace ihf {

enum class SceneRole {
	kTarget,
	kClutter,    // on the table near the target, some touching it
	kOccluder,   // placed between camera and target to reach an occlusion
	kBackground, // larger items further away
	kRoom,       // table slab, floor, wall
};

struct SceneObject {
	std::shared_ptr<const Mesh> mesh;
	Pose modelToWorld;
	SceneRole role = SceneRole::kClutter;
	int objId = 0; // BOP id of a model, 0 for primitives and the room
	// Share of its pixels the sensor loses (dark or shiny material).
	double dropout = 0;
	Footprint footprint; // on the table; unused for the room
	double height = 0;   // top above the table
};

struct SynthView {
	Pose worldToCamera;
	Eigen::Vector3d centre = Eigen::Vector3d::Zero(); // camera centre, world
	double distance = 0;  // camera centre to target origin, mm
	double elevation = 0; // radians above the table plane
	double azimuth = 0;   // radians
	double roll = 0;      // radians about the optical axis
	Eigen::Vector2d aim = Eigen::Vector2d::Zero(); // pixel of the target origin
};

struct SceneLayout {
	std::vector<SceneObject> objects; // objects[0] is the target
	SynthView view;
	Footprint table;       // the table top as placed (grown to hold everything)
	double tableHeight = 0; // table top above the floor
	bool wall = false;
};

struct LayoutParams {
	double distanceMin = 700, distanceMax = 800; // camera to target origin, mm
	double elevationMinDeg = 15, elevationMaxDeg = 75;
	double rollSigmaDeg = 3, rollMaxDeg = 8;
	int clutterMin = 4, clutterMax = 10;
	double touchProbability = 0.4;
	// Models set down upright (as a person would) rather than dropped.
	double uprightProbability = 0.6;  // clutter item placed touching the target
	double meshClutterShare = 0.5;   // clutter from other models vs primitives
	double clutterRadius = 350;      // mm around the target
	int backgroundMin = 3, backgroundMax = 10; // items further out on the table
	double wallProbability = 0.4;
	double darkProbability = 0.12;   // dark / shiny clutter with heavy dropout
	// Targets with dark or shiny patches: that share loses up to targetDropoutMax.
	double targetDropoutProbability = 0.3;
	double targetDropoutMax = 0.3;
	double minCameraClearance = 550; // mm camera to object: the Kinect sees nothing nearer than ~0.5 m
};

// Places model (resting pose restIndex, yaw about +z) with its footprint
// centred at xy on the table.
SceneObject placeOnTable(const PlaceableModel &model, int restIndex, double yaw,
			 const Eigen::Vector2d &xy, SceneRole role);

// Camera at distance from target, at the given elevation and azimuth, rolled
// about its axis and turned so that the target origin projects to aim.
SynthView lookAtTarget(const Eigen::Vector3d &target, double distance, double elevation,
		       double azimuth, double roll, const Eigen::Vector2d &aim,
		       const CameraIntrinsics &K);

// A random box, cylinder (upright or lying) or sphere with its size drawn
// log-uniformly; scale multiplies the size ranges.
PlaceableModel randomPrimitive(SynthRandom &rng, double scale = 1.0);

class LayoutSampler
{
public:
	LayoutSampler(const ModelLibrary &library, const CameraIntrinsics &K, LayoutParams params)
		: library_(library), K_(K), params_(params) {}

	// Target on the table and the camera; no clutter yet. The camera's
	// elevation is drawn up to min(elevationMaxDeg, elevationCapDeg).
	SceneLayout sampleBase(int targetId, SynthRandom &rng, double elevationCapDeg = 90) const;

	// Re-aims the camera (same position) so the target lands on aim.
	void reaim(SceneLayout &layout, const Eigen::Vector2d &aim) const;

	// Adds clutter and background objects around the target.
	void addClutter(SceneLayout &layout, int targetId, SynthRandom &rng) const;
	// The same, with the models of excludedIds kept off the table as clutter
	// (addClutter excludes the target only).
	void addClutter(SceneLayout &layout, const std::vector<int> &excludedIds,
			SynthRandom &rng) const;

	// Whether obj fits: no footprint overlap with the other objects (ignoring
	// index skip) and far enough from the camera.
	bool fits(const SceneLayout &layout, const SceneObject &obj, int skip = -1) const;

	// Distance along dir from the target's footprint centre at which obj's
	// footprint (at lateral offset) just clears the target's.
	double clearDistance(const SceneLayout &layout, SceneObject obj,
			     const Eigen::Vector2d &dir, const Eigen::Vector2d &lateral,
			     double gap) const;

	// Adds the table slab (grown to hold every object), the floor and
	// perhaps a wall behind the table.
	void addRoom(SceneLayout &layout, SynthRandom &rng) const;

	const LayoutParams &params() const { return params_; }
	const ModelLibrary &library() const { return library_; }

private:
	const ModelLibrary &library_;
	CameraIntrinsics K_;
	LayoutParams params_;
};

// Distance from a camera centre to the box an object standing on the table
// takes (its footprint times its height), mm.
double cameraClearance(const SceneObject &obj, const Eigen::Vector3d &cameraCentre);

// Moves obj so its footprint centre is at xy (keeps rotation and height).
void moveOnTable(SceneObject &obj, const Eigen::Vector2d &xy);

} // namespace ihf
