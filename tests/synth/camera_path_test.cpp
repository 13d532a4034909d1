// SPDX-License-Identifier: MIT
// The moving camera of `ihf synth --sequence`, the carried objects and the
// simulated detector: speed and turn-rate limits measured by finite
// differences of the camera poses at 30 Hz (and 240 Hz), pauses that hold
// still, a view that stays on the table, carries that start and end at
// their resting poses, and the detector's long-run miss share.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/synth/camera_path.h"
#include "core/synth/object_schedule.h"
#include "core/synth/sequence_detector.h"

namespace ihf {
namespace {

constexpr double kPi = std::numbers::pi;
const Eigen::Vector3d kCentre(100, -50, 40);

CameraPath makePath(CameraMotion style, uint64_t seed, double seconds = 20)
{
	CameraPathParams p;
	p.style = style;
	p.durationS = seconds;
	SynthRandom rng(seed);
	return CameraPath::sample(p, kinectV1Intrinsics(), kCentre, 0.7, rng);
}

struct Peaks {
	double speed = 0, turn = 0; // mm/s, rad/s
};

Peaks measure(const CameraPath &path, double rate)
{
	Peaks peaks;
	const int n = static_cast<int>(path.duration() * rate);
	Pose prev = path.worldToCamera(0);
	for (int i = 1; i <= n; ++i) {
		const Pose cur = path.worldToCamera(i / rate);
		peaks.speed = std::max(peaks.speed, (cur.inverse().t - prev.inverse().t).norm() * rate);
		peaks.turn = std::max(peaks.turn, rotationAngle(prev.R, cur.R) * rate);
		prev = cur;
	}
	return peaks;
}

TEST(CameraPath, SpeedAndTurnRateStayWithinTheLimits)
{
	for (CameraMotion style : {CameraMotion::kHandheld, CameraMotion::kRobot}) {
		double fastest = 0, quickest = 0;
		for (uint64_t seed = 0; seed < 6; ++seed) {
			SCOPED_TRACE(std::string(cameraMotionName(style)) + " seed " + std::to_string(seed));
			const CameraPath path = makePath(style, seed);
			EXPECT_GE(path.duration(), 20.0);
			for (double rate : {30.0, 240.0}) {
				const Peaks p = measure(path, rate);
				EXPECT_LE(p.speed, 500.0) << rate;
				EXPECT_LE(p.turn, 90.0 * kPi / 180.0) << rate;
				fastest = std::max(fastest, p.speed);
				quickest = std::max(quickest, p.turn);
			}
			EXPECT_GE(path.quickTurns(), 1);
		}
		// The limits are used, not just respected: quick turns come near them.
		EXPECT_GT(fastest, 250.0) << cameraMotionName(style);
		EXPECT_GT(quickest, 0.6 * 90.0 * kPi / 180.0) << cameraMotionName(style);
	}
}

TEST(CameraPath, PausesHoldStillAndTheViewStaysOnTheTable)
{
	const CameraIntrinsics K = kinectV1Intrinsics();
	for (CameraMotion style : {CameraMotion::kHandheld, CameraMotion::kRobot}) {
		for (uint64_t seed = 0; seed < 4; ++seed) {
			SCOPED_TRACE(std::string(cameraMotionName(style)) + " seed " + std::to_string(seed));
			const CameraPath path = makePath(style, seed, 12);
			ASSERT_GE(path.pauses().size(), 1u);
			for (const PathPause &pause : path.pauses()) {
				EXPECT_GE(pause.end - pause.start, 0.5 - 1e-9);
				EXPECT_LE(pause.end - pause.start, 2.0 * 1.01 * 1.01 + 1e-9); // retiming may stretch it
				const Pose a = path.worldToCamera(pause.start), b = path.worldToCamera(pause.end);
				const Pose mid = path.worldToCamera(0.5 * (pause.start + pause.end));
				// A robot holds still (to rounding); a hand only shakes (mm,
				// tenths of a degree).
				const double still = style == CameraMotion::kRobot ? 1e-6 : 8.0;
				EXPECT_LE((a.inverse().t - mid.inverse().t).norm(), still);
				EXPECT_LE((a.inverse().t - b.inverse().t).norm(), still);
				EXPECT_LE(rotationAngle(a.R, mid.R), style == CameraMotion::kRobot ? 1e-6 : 0.02);
			}
			for (double t = 0; t < path.duration(); t += 0.1) {
				const Pose view = path.worldToCamera(t);
				const Eigen::Vector3d q = view.apply(kCentre);
				ASSERT_GT(q.z(), 0);
				const Eigen::Vector2d uv = K.project(q);
				EXPECT_GT(uv.x(), 0.1 * K.width) << t;
				EXPECT_LT(uv.x(), 0.9 * K.width) << t;
				EXPECT_GT(uv.y(), 0.1 * K.height) << t;
				EXPECT_LT(uv.y(), 0.9 * K.height) << t;
				const double d = (view.inverse().t - kCentre).norm();
				EXPECT_GT(d, 600 - 130);
				EXPECT_LT(d, 1100 + 130);
				// Above the table top.
				EXPECT_GT(view.inverse().t.z(), 100);
			}
		}
	}
}

TEST(CameraPath, SameSeedSamePathAndOnlyTheHandShakes)
{
	const CameraPath a = makePath(CameraMotion::kHandheld, 3), b = makePath(CameraMotion::kHandheld, 3);
	const CameraPath c = makePath(CameraMotion::kHandheld, 4);
	bool differs = false;
	for (double t = 0; t < 20; t += 0.37) {
		const Pose pa = a.worldToCamera(t), pb = b.worldToCamera(t), pc = c.worldToCamera(t);
		EXPECT_EQ(pa.R, pb.R);
		EXPECT_EQ(pa.t, pb.t);
		differs = differs || (pa.t - pc.t).norm() > 1.0;
	}
	EXPECT_TRUE(differs);
	EXPECT_GT(a.shakeSpeedBound(), 0.0);
	EXPECT_EQ(makePath(CameraMotion::kRobot, 3).shakeSpeedBound(), 0.0);
	EXPECT_EQ(cameraMotionNamed("robot"), CameraMotion::kRobot);
	EXPECT_EQ(cameraMotionNamed("mixed"), CameraMotion::kMixed);
	EXPECT_FALSE(cameraMotionNamed("jog"));
}

TEST(ObjectSchedule, ACarryLiftsMovesAndSetsDown)
{
	Pose a, b;
	a.t = {0, 0, 10};
	b.R = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	b.t = {200, 100, 10};
	ObjectSchedule s(a);
	Carry c;
	c.start = 2;
	c.end = 3;
	c.from = a;
	c.to = b;
	c.liftFrom = c.liftTo = 80;
	s.add(c);
	EXPECT_TRUE(s.resting(1.9));
	EXPECT_FALSE(s.resting(2.5));
	EXPECT_TRUE(s.resting(3.0));
	EXPECT_EQ(s.modelToWorld(0).t, a.t);
	EXPECT_EQ(s.modelToWorld(1.99).t, a.t);
	EXPECT_EQ(s.modelToWorld(3.0).t, b.t);
	EXPECT_EQ(s.modelToWorld(9.0).R, b.R);
	// Lifted before it moves across, lowered after: over the middle of
	// the carry it flies at the lift height.
	EXPECT_NEAR(s.modelToWorld(2.25).t.z(), 90, 1e-9);
	EXPECT_NEAR(s.modelToWorld(2.25).t.x(), 0, 1e-9);
	EXPECT_NEAR(s.modelToWorld(2.5).t.z(), 90, 1e-9);
	EXPECT_NEAR(s.modelToWorld(2.5).t.x(), 100, 1e-9);
	EXPECT_NEAR(rotationAngle(s.modelToWorld(2.5).R, a.R), 0.5, 1e-9);
	// Continuous: small steps move it a little.
	for (double t = 2; t < 3; t += 0.01)
		EXPECT_LT((s.modelToWorld(t + 0.001).t - s.modelToWorld(t).t).norm(), 1.0) << t;

	ObjectSchedule away(a), down(b);
	c.kind = CarryKind::kTakeAway;
	away.add(c);
	c.kind = CarryKind::kPutDown;
	down.add(c);
	EXPECT_TRUE(away.present(2.9));
	EXPECT_FALSE(away.present(3.0));
	EXPECT_FALSE(down.present(1.9));
	EXPECT_TRUE(down.present(2.0));
	EXPECT_TRUE(down.resting(3.5));
}

TEST(SequenceDetector, MissesComeInShortRunsAtTheAskedShare)
{
	DetectorParams p;
	for (double m : {0.03, 0.2}) {
		p.missProbability = m;
		SynthRandom rng(11);
		const std::vector<uint8_t> miss = detectorMisses(200000, p, rng);
		int missed = 0, runs = 0;
		for (size_t i = 0; i < miss.size(); ++i) {
			missed += miss[i];
			runs += miss[i] && (i == 0 || !miss[i - 1]);
		}
		EXPECT_NEAR(missed / 200000.0, m, 0.15 * m) << m;
		// Mean run 1 / (1 - persistence) = 2 frames.
		EXPECT_NEAR(static_cast<double>(missed) / runs, 2.0, 0.15) << m;
	}
	p.missProbability = 0;
	SynthRandom rng(1);
	for (uint8_t v : detectorMisses(1000, p, rng))
		EXPECT_EQ(v, 0);
	p.missProbability = 1;
	for (uint8_t v : detectorMisses(1000, p, rng))
		EXPECT_EQ(v, 1);

	GtInfo info;
	info.bboxObj = {100, 80, 60, 40};
	info.pxCountAll = 1000;
	info.pxCountVisib = 150;
	info.visibFract = 0.15;
	p.missProbability = 0;
	auto box = detectObject(info, false, 640, 480, 2, 7, 5, rng, p);
	ASSERT_TRUE(box);
	EXPECT_EQ(box->sceneId, 2);
	EXPECT_EQ(box->imageId, 7);
	EXPECT_EQ(box->categoryId, 5);
	EXPECT_FALSE(detectObject(info, true, 640, 480, 2, 7, 5, rng, p));
	info.visibFract = 0.09;
	EXPECT_FALSE(detectObject(info, false, 640, 480, 2, 7, 5, rng, p));
}

} // namespace
} // namespace ihf
