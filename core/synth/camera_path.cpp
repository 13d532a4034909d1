// SPDX-License-Identifier: MIT
#include "core/synth/camera_path.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/geometry/rotation.h"
#include "core/synth/scene_layout.h"

namespace ihf {

namespace {

// Quintic Hermite basis with zero acceleration at both ends: position and
// velocity continuous through a key, acceleration zero there (so C2).
struct Quintic {
	double h0, h1, h4, h5;
	explicit Quintic(double s)
	{
		const double s3 = s * s * s, s4 = s3 * s, s5 = s4 * s;
		h0 = 1 - 10 * s3 + 15 * s4 - 6 * s5;
		h1 = s - 6 * s3 + 8 * s4 - 3 * s5;
		h4 = -4 * s3 + 7 * s4 - 3 * s5;
		h5 = 10 * s3 - 15 * s4 + 6 * s5;
	}
	template<class T>
	T operator()(const T &x0, const T &v0, const T &x1, const T &v1, double T_) const
	{
		return h0 * x0 + (h1 * T_) * v0 + h5 * x1 + (h4 * T_) * v1;
	}
};

// A look-at camera at p towards g, rolled about its axis (the convention of
// lookAtTarget: x right and horizontal before the roll, y down the image).
Pose lookAtPose(const Eigen::Vector3d &p, const Eigen::Vector3d &g, double roll,
		const CameraIntrinsics &K)
{
	const Eigen::Vector3d d = p - g;
	const double dist = d.norm();
	const double elevation = std::asin(std::clamp(d.z() / dist, -1.0, 1.0));
	const double azimuth = std::atan2(d.y(), d.x());
	return lookAtTarget(g, dist, elevation, azimuth, roll, Eigen::Vector2d(K.cx, K.cy), K)
		.worldToCamera;
}

} // namespace

const char *cameraMotionName(CameraMotion motion)
{
	switch (motion) {
	case CameraMotion::kHandheld:
		return "handheld";
	case CameraMotion::kRobot:
		return "robot";
	case CameraMotion::kMixed:
		return "mixed";
	}
	return "?";
}

std::optional<CameraMotion> cameraMotionNamed(std::string_view name)
{
	for (CameraMotion m : {CameraMotion::kHandheld, CameraMotion::kRobot, CameraMotion::kMixed})
		if (name == cameraMotionName(m))
			return m;
	return std::nullopt;
}

CameraPath CameraPath::sample(const CameraPathParams &p, const CameraIntrinsics &K,
			      const Eigen::Vector3d &centre, double baseAzimuth, SynthRandom &rng)
{
	CameraPath path;
	path.K_ = K;
	path.style_ = p.style == CameraMotion::kRobot ? CameraMotion::kRobot : CameraMotion::kHandheld;
	const bool handheld = path.style_ == CameraMotion::kHandheld;

	// The hand's shake: a slow sway, a faster wobble and the physiological
	// tremor, per axis, each wave's speed bounded by 2 pi f A.
	if (handheld) {
		const double freqs[3] = {1.5, 4.0, 9.0};
		const double moveMm[3] = {2.0, 0.6, 0.2};
		const double turnDeg[3] = {0.3, 0.12, 0.05};
		double bound[6] = {};
		for (int axis = 0; axis < 6; ++axis) {
			for (int w = 0; w < 3; ++w) {
				Wave wave;
				const double f = freqs[w] * rng.uniform(0.7, 1.3);
				const double a = (axis < 3 ? moveMm[w] : radians(turnDeg[w])) * rng.uniform(0.6, 1.0) * p.shake;
				wave.amplitude = a;
				wave.omega = 2 * std::numbers::pi * f;
				wave.phase = rng.uniform(0, 2 * std::numbers::pi);
				bound[axis] += wave.omega * wave.amplitude;
				path.shake_[axis].push_back(wave);
			}
		}
		path.shakeSpeed_ = Eigen::Vector3d(bound[0], bound[1], bound[2]).norm();
		path.shakeTurn_ = Eigen::Vector3d(bound[3], bound[4], bound[5]).norm();
	}
	// Room for the shake under the limits, and a margin for the sampling of
	// the segments' peaks.
	const double vLimit = 0.97 * p.maxSpeedMmS - path.shakeSpeed_;
	const double wLimit = 0.97 * radians(p.maxTurnDegS) - path.shakeTurn_;

	// Waypoints: azimuth within the arc, elevation, distance, look-at point.
	const double arc = radians(p.arcHalfDeg);
	double azimuth = baseAzimuth + rng.uniform(-0.5, 0.5) * arc;
	double elevation = radians(rng.uniform(p.elevationMinDeg, p.elevationMaxDeg));
	double distance = rng.uniform(p.distanceMin, p.distanceMax);
	auto randomLook = [&]() {
		const double r = p.lookRadius * std::sqrt(rng.uniform01());
		const double a = rng.uniform(0, 2 * std::numbers::pi);
		return Eigen::Vector3d(centre + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0));
	};
	Eigen::Vector3d look = randomLook();
	auto rollDraw = [&]() {
		return handheld ? radians(std::clamp(rng.normal() * p.rollSigmaDeg, -2 * p.rollSigmaDeg,
						      2 * p.rollSigmaDeg))
				: 0.0;
	};
	auto place = [&](Key &k) {
		k.g = look;
		k.p = look + distance * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
							std::cos(elevation) * std::sin(azimuth),
							std::sin(elevation));
	};
	Key first;
	place(first);
	first.roll = rollDraw();
	first.stop = true;
	path.keys_.push_back(first);

	// One pause and one quick turn are placed for sure in sequences long
	// enough to hold them; more come at random.
	const bool longEnough = p.durationS >= 4.0;
	const double forcedPause = rng.uniform(0.2, 0.7) * p.durationS;
	const double forcedTurn = rng.uniform(0.2, 0.8) * p.durationS;
	bool paused = false, turned = false;
	while (path.keys_.back().t < p.durationS) {
		const Key &prev = path.keys_.back();
		const bool quick = rng.chance(p.quickTurnProbability) ||
				   (longEnough && !turned && prev.t >= forcedTurn);
		if (quick) {
			// Swing the view to another part of the table.
			const double step = radians(rng.uniform(25, 50));
			azimuth += rng.chance(0.5) ? step : -step;
			const Eigen::Vector3d from = look - centre;
			const double a = std::atan2(from.y(), from.x()) + std::numbers::pi + rng.uniform(-0.6, 0.6);
			const double r = p.lookRadius * rng.uniform(0.6, 1.0);
			look = centre + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0);
		} else {
			azimuth += radians(rng.uniform(-25, 25));
			elevation += radians(rng.uniform(-12, 12));
			distance += rng.uniform(-150, 150);
			const Eigen::Vector3d target = randomLook();
			look += rng.uniform(0.3, 1.0) * (target - look);
		}
		// Reflect at the ends of the arc and of the ranges.
		const double lo = baseAzimuth - arc, hi = baseAzimuth + arc;
		if (azimuth > hi)
			azimuth = std::max(lo, 2 * hi - azimuth);
		if (azimuth < lo)
			azimuth = std::min(hi, 2 * lo - azimuth);
		elevation = std::clamp(elevation, radians(p.elevationMinDeg), radians(p.elevationMaxDeg));
		distance = std::clamp(distance, p.distanceMin, p.distanceMax);

		Key k;
		place(k);
		k.roll = rollDraw();
		k.stop = !handheld;
		// Duration from the distance and the turn at a share of the limits
		// (a rest-to-rest quintic peaks at 1.875x its mean speed).
		const double fraction = quick ? rng.uniform(0.85, 0.95) : rng.uniform(0.25, 0.6);
		const Eigen::Vector3d d0 = (prev.g - prev.p).normalized(), d1 = (k.g - k.p).normalized();
		const double turn = std::acos(std::clamp(d0.dot(d1), -1.0, 1.0)) + std::abs(k.roll - prev.roll);
		const double T = 1.875 * std::max({(k.p - prev.p).norm() / (fraction * vLimit),
						    turn / (fraction * wLimit), 0.3});
		k.t = prev.t + T;
		turned = turned || quick;
		path.quickTurns_ += quick ? 1 : 0;
		path.keys_.push_back(k);

		const bool pause = rng.chance(p.pauseProbability) || (longEnough && !paused && k.t >= forcedPause);
		if (pause && k.t < p.durationS) {
			path.keys_.back().stop = true;
			Key hold = path.keys_.back();
			hold.t += rng.uniform(p.pauseMinS, p.pauseMaxS);
			path.keys_.push_back(hold);
			paused = true;
		}
	}
	path.keys_.back().stop = true;

	// Slow every segment whose peak is over a limit, until none is. Through
	// a waypoint the velocity depends on both neighbours' durations, so this
	// iterates; rest-to-rest segments scale exactly, hence the fallback.
	std::vector<double> durations;
	for (size_t k = 1; k < path.keys_.size(); ++k)
		durations.push_back(path.keys_[k].t - path.keys_[k - 1].t);
	auto retime = [&]() {
		for (size_t k = 1; k < path.keys_.size(); ++k)
			path.keys_[k].t = path.keys_[k - 1].t + durations[k - 1];
		path.setVelocities();
	};
	retime();
	for (int iteration = 0; iteration < 200; ++iteration) {
		if (iteration == 100)
			for (Key &k : path.keys_)
				k.stop = true;
		bool over = false;
		for (size_t k = 0; k + 1 < path.keys_.size(); ++k) {
			const auto [lin, ang] = path.segmentPeak(k);
			const double ratio = std::max(lin / vLimit, ang / wLimit);
			if (ratio > 1.0) {
				durations[k] *= ratio * 1.01;
				over = true;
			}
		}
		if (!over)
			break;
		retime();
	}

	for (size_t k = 0; k + 1 < path.keys_.size(); ++k) {
		const Key &a = path.keys_[k], &b = path.keys_[k + 1];
		if (a.p == b.p && a.g == b.g && a.roll == b.roll)
			path.pauses_.push_back({a.t, b.t});
	}
	return path;
}

void CameraPath::setVelocities()
{
	const size_t n = keys_.size();
	for (size_t k = 0; k < n; ++k) {
		Key &key = keys_[k];
		if (key.stop || k == 0 || k + 1 == n) {
			key.vp.setZero();
			key.vg.setZero();
			key.vroll = 0;
			continue;
		}
		// Catmull-Rom tangent, damped so turns do not overshoot.
		const Key &a = keys_[k - 1], &b = keys_[k + 1];
		const double span = b.t - a.t;
		key.vp = 0.8 * (b.p - a.p) / span;
		key.vg = 0.8 * (b.g - a.g) / span;
		key.vroll = 0.8 * (b.roll - a.roll) / span;
	}
}

Pose CameraPath::basePoseInSegment(size_t k, double t) const
{
	const Key &a = keys_[k], &b = keys_[k + 1];
	const double T = b.t - a.t;
	const Quintic q(std::clamp((t - a.t) / T, 0.0, 1.0));
	const Eigen::Vector3d p = q(a.p, a.vp, b.p, b.vp, T);
	const Eigen::Vector3d g = q(a.g, a.vg, b.g, b.vg, T);
	const double roll = q(a.roll, a.vroll, b.roll, b.vroll, T);
	return lookAtPose(p, g, roll, K_);
}

Pose CameraPath::basePose(double t) const
{
	if (keys_.size() < 2)
		return keys_.empty() ? Pose{} : lookAtPose(keys_[0].p, keys_[0].g, keys_[0].roll, K_);
	t = std::clamp(t, 0.0, duration());
	auto it = std::upper_bound(keys_.begin(), keys_.end(), t,
				   [](double v, const Key &k) { return v < k.t; });
	size_t k = static_cast<size_t>(std::max<std::ptrdiff_t>(it - keys_.begin(), 1)) - 1;
	k = std::min(k, keys_.size() - 2);
	return basePoseInSegment(k, t);
}

std::pair<double, double> CameraPath::segmentPeak(size_t k) const
{
	const double t0 = keys_[k].t, T = keys_[k + 1].t - t0;
	const int steps = std::max(8, static_cast<int>(std::ceil(T * 240.0)));
	const double h = T / steps;
	double lin = 0, ang = 0;
	Pose prev = basePoseInSegment(k, t0);
	Eigen::Vector3d prevC = prev.inverse().t;
	for (int i = 1; i <= steps; ++i) {
		const Pose cur = basePoseInSegment(k, t0 + i * h);
		const Eigen::Vector3d c = cur.inverse().t;
		lin = std::max(lin, (c - prevC).norm() / h);
		ang = std::max(ang, rotationAngle(prev.R, cur.R) / h);
		prev = cur;
		prevC = c;
	}
	return {lin, ang};
}

Pose CameraPath::worldToCamera(double t) const
{
	Pose base = basePose(t);
	if (style_ != CameraMotion::kHandheld)
		return base;
	Eigen::Vector3d move, turn;
	for (int axis = 0; axis < 6; ++axis) {
		double v = 0;
		for (const Wave &w : shake_[axis])
			v += w.amplitude * std::sin(w.omega * t + w.phase);
		(axis < 3 ? move[axis] : turn[axis - 3]) = v;
	}
	// The shake in the camera frame: x_cam' = Rs x_cam + s.
	const double angle = turn.norm();
	const Eigen::Matrix3d Rs = angle > 0 ? Eigen::AngleAxisd(angle, turn / angle).toRotationMatrix()
					     : Eigen::Matrix3d::Identity();
	return Pose{Rs, move} * base;
}

} // namespace ihf
