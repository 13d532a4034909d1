// SPDX-License-Identifier: MIT
#pragma once

// The trajectory of a moving depth camera over a table, as a person holding
// it or a robot arm carrying it moves it: waypoints around the table (a
// distance and elevation from a look-at point that wanders over the table's
// centre region, an azimuth within an arc on one side of the table), joined
// by quintic segments (continuous position, velocity and acceleration),
// pauses where the camera holds still, and quick turns that swing the view
// to another part of the table near the speed limits.
//
//  - handheld: the path flows through its waypoints (velocity kept through
//    a waypoint, Catmull-Rom tangents), the camera rolls a little, and a
//    hand's shake (sums of sinusoids of 1-12 Hz, ~2 mm and ~0.3 deg) rides
//    on top, also during pauses;
//  - robot: point-to-point moves that start and end at rest (minimum-jerk
//    profiles, as an arm runs a program of poses), no roll, no shake.
//
// Linear speed (of the camera centre) and angular speed never exceed the
// limits: each segment is slowed until its peak, sampled at 240 Hz, fits
// the limit minus the shake's analytic speed bound.

#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/pose.h"
#include "core/synth/synth_random.h"

namespace ihf {

enum class CameraMotion {
	kHandheld,
	kRobot,
	kMixed, // each sequence draws handheld or robot
};

// The name `ihf synth --motion` takes, and the style of a name.
const char *cameraMotionName(CameraMotion motion);
std::optional<CameraMotion> cameraMotionNamed(std::string_view name);

struct CameraPathParams {
	CameraMotion style = CameraMotion::kHandheld; // handheld or robot
	double durationS = 10;
	double maxSpeedMmS = 500;  // camera centre
	double maxTurnDegS = 90;   // camera rotation
	double distanceMin = 600, distanceMax = 1100; // camera centre to the look-at point, mm
	double elevationMinDeg = 20, elevationMaxDeg = 55;
	double arcHalfDeg = 75;    // azimuths within this of the base azimuth
	double lookRadius = 120;   // the look-at point wanders this far from the centre, mm
	double pauseProbability = 0.25; // after a segment
	double pauseMinS = 0.5, pauseMaxS = 2.0;
	double quickTurnProbability = 0.2; // a segment is a quick turn
	double shake = 1.0;        // hand-shake amplitude factor (handheld only)
	double rollSigmaDeg = 3;   // handheld roll at the waypoints
};

// An interval over which the path (without the hand's shake) holds still.
struct PathPause {
	double start = 0, end = 0;
};

class CameraPath
{
public:
	// A path of at least p.durationS seconds around centre (world frame,
	// table top z = 0), its azimuths within p.arcHalfDeg of baseAzimuth.
	static CameraPath sample(const CameraPathParams &p, const CameraIntrinsics &K,
				 const Eigen::Vector3d &centre, double baseAzimuth, SynthRandom &rng);

	Pose worldToCamera(double t) const;
	Eigen::Vector3d cameraCentre(double t) const { return worldToCamera(t).inverse().t; }

	CameraMotion style() const { return style_; }
	double duration() const { return keys_.empty() ? 0.0 : keys_.back().t; }
	const std::vector<PathPause> &pauses() const { return pauses_; }
	int quickTurns() const { return quickTurns_; }
	// Bounds of the shake's linear (mm/s) and angular (rad/s) speed.
	double shakeSpeedBound() const { return shakeSpeed_; }
	double shakeTurnBound() const { return shakeTurn_; }

private:
	// Camera centre p, look-at point g and roll, with their rates.
	struct Key {
		double t = 0;
		Eigen::Vector3d p = Eigen::Vector3d::Zero(), g = Eigen::Vector3d::Zero();
		double roll = 0;
		Eigen::Vector3d vp = Eigen::Vector3d::Zero(), vg = Eigen::Vector3d::Zero();
		double vroll = 0;
		bool stop = false; // the path comes to rest here
	};
	struct Wave {
		double amplitude = 0, omega = 0, phase = 0;
	};

	Pose basePose(double t) const;
	Pose basePoseInSegment(size_t k, double t) const;
	void setVelocities();
	// Peak linear and angular speed of segment k without the shake.
	std::pair<double, double> segmentPeak(size_t k) const;

	CameraIntrinsics K_;
	CameraMotion style_ = CameraMotion::kHandheld;
	std::vector<Key> keys_;
	std::vector<PathPause> pauses_;
	int quickTurns_ = 0;
	// Hand shake: three waves per translation and rotation axis (camera frame).
	std::vector<Wave> shake_[6];
	double shakeSpeed_ = 0, shakeTurn_ = 0;
};

} // namespace ihf
