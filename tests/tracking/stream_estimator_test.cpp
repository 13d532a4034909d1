// SPDX-License-Identifier: MIT
// Tracking through a stream (core/tracking/stream_estimator.h): an object
// detected once is then tracked from frame to frame while it moves; a box
// is matched to its track by overlap or by the detector's track id; inside
// a frame budget tracked boxes run first and detections that do not fit
// wait, oldest first, and none waits longer than maxDeferFrames; an object
// moved, turned or taken away is detected again; bad boxes get a status and
// the stream goes on. Scenes are a small LM-O forest's object rendered in
// front of a wall; budgets run on a step clock.

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/rotation.h"
#include "core/tracking/stream_estimator.h"
#include "core/training/view_template_builder.h"
#include "tests/runtime/small_model.h"

namespace ihf {
namespace {

constexpr int64_t kMs = 1000000;
// A frame with room for one detection and a tracked box, not for two
// detections: a detection of these boxes reads the step clock 33 times.
constexpr float kOneDetectionMs = 40.0f;

double degrees(const Pose &a, const Pose &b)
{
	return rotationAngle(a.R, b.R) * 180.0 / M_PI;
}

double mm(const Pose &a, const Pose &b)
{
	return (a.t - b.t).norm();
}

// A turn of `deg` degrees about `axis` (camera frame) of the pose, about
// the pose's own origin.
Pose turned(const Pose &p, const Eigen::Vector3d &axis, double deg)
{
	const Eigen::Matrix3d R = Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
	return {R * p.R, p.t};
}

class StreamEstimatorTest : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		model_ = new test::SmallModel(test::trainSmallModel(1, 11, 20, 2));
		ASSERT_TRUE(model_->model);
		auto points = buildViewTemplatePoints(model_->model->mesh(), model_->model->params().diameter, {40, 32});
		ASSERT_TRUE(points) << points.error().message;
		model_->model->attachViewTemplates(40, 32, std::move(*points));
	}
	static void TearDownTestSuite() { delete model_; }

	const ObjectModel &model() const { return *model_->model; }

	// The object at each pose in front of a wall 1 m away; the box of each.
	struct Scene {
		DepthImageMm depth{640, 480, 0.0f};
		std::vector<PixelBox> boxes;
	};
	Scene render(const std::vector<Pose> &poses) const
	{
		Scene s;
		for (const Pose &p : poses)
			s.boxes.push_back(test::renderInto(model(), p, s.depth));
		for (int y = 0; y < s.depth.height(); ++y)
			for (int x = 0; x < s.depth.width(); ++x)
				if (!(s.depth.at(x, y) > 0))
					s.depth.at(x, y) = 1000.0f;
		return s;
	}

	std::vector<StreamBox> boxesOf(const Scene &s) const
	{
		std::vector<StreamBox> out;
		for (const PixelBox &b : s.boxes)
			out.push_back({1, b, 0, &model()});
		return out;
	}

	static EstimatorConfig detection()
	{
		EstimatorConfig c;
		c.iterations = 0;
		return c;
	}

	// A pose moving a few millimetres and about a degree a frame, as an
	// object seen by a camera moving at ~0.1 m/s.
	Pose start() const { return test::viewAt(*model_, 37, {40, -30, 780}); }
	static Pose moved(const Pose &p0, int frame)
	{
		Pose p = turned(p0, {0.3, 1.0, 0.2}, 1.2 * frame);
		p.t += Eigen::Vector3d(3.0, -1.5, 2.0) * frame;
		return p;
	}

	std::vector<StreamResult> run(StreamEstimator &s, uint64_t frame, const Scene &scene,
				      const std::vector<StreamBox> &boxes, float budgetMs = 0,
				      const EstimatorConfig &c = detection())
	{
		std::vector<StreamResult> r(boxes.size());
		s.estimateFrame(frame, scene.depth.view(), test::kKinect, boxes, c, budgetMs, r);
		return r;
	}

	static test::SmallModel *model_;
};

test::SmallModel *StreamEstimatorTest::model_ = nullptr;

TEST_F(StreamEstimatorTest, AMovingObjectIsDetectedOnceThenTracked)
{
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	ASSERT_TRUE(stream.valid());
	const Pose p0 = start();
	int trackId = 0;
	for (int f = 0; f < 12; ++f) {
		const Pose truth = moved(p0, f);
		const Scene scene = render({truth});
		const std::vector<StreamResult> r = run(stream, static_cast<uint64_t>(f), scene, boxesOf(scene));
		ASSERT_EQ(r.size(), 1u);
		ASSERT_TRUE(r[0].estimate.found) << "frame " << f << ": " << r[0].estimate.reason;
		EXPECT_EQ(r[0].mode, f == 0 ? BoxMode::kDetect : BoxMode::kTrack) << "frame " << f;
		EXPECT_LT(mm(r[0].estimate.pose, truth), 5.0) << "frame " << f;
		EXPECT_LT(degrees(r[0].estimate.pose, truth), 3.0) << "frame " << f;
		if (f == 0)
			trackId = r[0].trackId;
		EXPECT_EQ(r[0].trackId, trackId);
		EXPECT_GT(r[0].estimate.confidence, 0.0f);
	}
	EXPECT_EQ(stream.stats().detected, 1u);
	EXPECT_EQ(stream.stats().tracked, 11u);
	EXPECT_EQ(stream.stats().started, 1u);
	EXPECT_EQ(stream.stats().trackTime.calls, 11u);
}

TEST_F(StreamEstimatorTest, WithTrackingOffEveryBoxIsDetected)
{
	PoseEstimator detector;
	TrackerConfig off;
	off.enabled = false;
	StreamEstimator stream(detector, off);
	for (int f = 0; f < 3; ++f) {
		const Scene scene = render({moved(start(), f)});
		const std::vector<StreamResult> r = run(stream, static_cast<uint64_t>(f), scene, boxesOf(scene));
		EXPECT_EQ(r[0].mode, BoxMode::kDetect);
		EXPECT_FALSE(r[0].tracked);
	}
	EXPECT_EQ(stream.stats().tracked, 0u);
}

TEST_F(StreamEstimatorTest, ATrackedPoseIsTheDetectorsScoreOfThatPose)
{
	// The tracked box is scored as a detection scores it: same crop, same
	// scorer.
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	const Scene s0 = render({moved(start(), 0)});
	run(stream, 0, s0, boxesOf(s0));
	const Scene s1 = render({moved(start(), 1)});
	const std::vector<StreamResult> r = run(stream, 1, s1, boxesOf(s1));
	ASSERT_EQ(r[0].mode, BoxMode::kTrack);
	EstimatorConfig c = detection();
	c.windowPixels = 4000; // the tracker's
	auto scored = detector.scorePose(s1.depth.view(), test::kKinect, s1.boxes[0], model(), c, r[0].estimate.pose);
	ASSERT_TRUE(scored);
	EXPECT_NEAR(scored->score, r[0].estimate.score.score, 0.05f);
}

TEST_F(StreamEstimatorTest, TheDetectorsTrackIdWinsOverOverlap)
{
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	const Pose a = test::viewAt(*model_, 37, {-120, -20, 800}), b = test::viewAt(*model_, 12, {110, 30, 800});
	Scene s0 = render({a, b});
	std::vector<StreamBox> boxes = boxesOf(s0);
	boxes[0].trackId = 7;
	boxes[1].trackId = 9;
	std::vector<StreamResult> r = run(stream, 0, s0, boxes);
	EXPECT_EQ(r[0].trackId, 7);
	EXPECT_EQ(r[1].trackId, 9);
	// The same boxes in the other order keep their identities.
	std::swap(boxes[0], boxes[1]);
	r = run(stream, 1, s0, boxes);
	EXPECT_EQ(r[0].trackId, 9);
	EXPECT_EQ(r[1].trackId, 7);
	EXPECT_EQ(r[0].mode, BoxMode::kTrack);
	EXPECT_EQ(r[1].mode, BoxMode::kTrack);
	// Without ids, the overlap keeps them too.
	boxes[0].trackId = boxes[1].trackId = 0;
	r = run(stream, 2, s0, boxes);
	EXPECT_EQ(r[0].trackId, 9);
	EXPECT_EQ(r[1].trackId, 7);
}

TEST_F(StreamEstimatorTest, ATrackIdHeldByAnotherTrackIsNotGivenTwice)
{
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	const Pose a = test::viewAt(*model_, 37, {-120, -20, 800}), b = test::viewAt(*model_, 12, {110, 30, 800});
	Scene s0 = render({a, b});
	std::vector<StreamBox> boxes = boxesOf(s0);
	// Two boxes of the frame given the same new id: one track takes it.
	boxes[0].trackId = boxes[1].trackId = 7;
	std::vector<StreamResult> r = run(stream, 0, s0, boxes);
	EXPECT_EQ(r[0].trackId, 7);
	EXPECT_GT(r[1].trackId, 0);
	EXPECT_NE(r[1].trackId, 7);
	EXPECT_EQ(stream.activeTracks(), 2);
	// The second box, now carrying the first one's id, is still matched to
	// its own track, by overlap.
	const int second = r[1].trackId;
	r = run(stream, 1, s0, boxes);
	EXPECT_EQ(r[0].trackId, 7);
	EXPECT_EQ(r[1].trackId, second);
	EXPECT_EQ(r[1].mode, BoxMode::kTrack);
	// A box of another object with id 7 starts a track of its own id.
	std::vector<StreamBox> other = {boxes[0], boxes[1], boxes[0]};
	other[2].objId = 2;
	other[2].trackId = 7;
	std::vector<StreamResult> r3 = run(stream, 2, s0, other);
	EXPECT_EQ(r3[0].trackId, 7);
	EXPECT_EQ(r3[1].trackId, second);
	EXPECT_GT(r3[2].trackId, 0);
	EXPECT_NE(r3[2].trackId, 7);
	EXPECT_NE(r3[2].trackId, second);
	EXPECT_EQ(stream.activeTracks(), 3);
}

TEST_F(StreamEstimatorTest, TrackedBoxesRunFirstAndDetectionsThatDoNotFitWait)
{
	test::StepClock clock(kMs);
	PoseEstimator detector({}, &clock);
	TrackerConfig tc;
	tc.detectMinMs = 20;
	tc.maxDeferFrames = 3;
	StreamEstimator stream(detector, tc, &clock);
	const Pose a = test::viewAt(*model_, 37, {-150, -40, 800}), b = test::viewAt(*model_, 12, {0, 60, 800}),
		   c = test::viewAt(*model_, 25, {150, -40, 800});
	const Scene scene = render({a, b, c});
	const std::vector<StreamBox> all = boxesOf(scene);
	// Frame 0: room for one detection of the three.
	std::vector<StreamResult> r = run(stream, 0, scene, all, kOneDetectionMs);
	ASSERT_EQ(std::count_if(r.begin(), r.end(), [](const StreamResult &x) { return x.mode == BoxMode::kDetect; }),
		  1);
	ASSERT_EQ(std::count_if(r.begin(), r.end(), [](const StreamResult &x) { return x.mode == BoxMode::kDeferred; }),
		  2);
	EXPECT_EQ(r[0].mode, BoxMode::kDetect); // the frame's order among equal waits
	for (const StreamResult &x : r)
		if (x.mode == BoxMode::kDeferred) {
			EXPECT_FALSE(x.estimate.found);
			EXPECT_GT(x.trackId, 0);
		}
	EXPECT_EQ(stream.stats().deferred, 2u);
	// Frame 1: the tracked box runs first although it is listed last; of
	// the waiting two, one more fits.
	std::vector<StreamBox> reordered{all[1], all[2], all[0]};
	r = run(stream, 1, scene, reordered, kOneDetectionMs);
	EXPECT_EQ(r[2].mode, BoxMode::kTrack);
	for (int i = 0; i < 2; ++i)
		if (r[i].mode == BoxMode::kDetect) {
			EXPECT_GT(r[i].startNs, r[2].startNs);
			EXPECT_EQ(r[i].waited, 1);
		}
	EXPECT_EQ(std::count_if(r.begin(), r.end(), [](const StreamResult &x) { return x.mode == BoxMode::kDetect; }),
		  1);
	// Frame 2, with no room at all: the box that has waited two frames is
	// due and runs anyway (forced); every box has had its detection.
	r = run(stream, 2, scene, reordered, 1);
	int detectedNow = 0;
	for (const StreamResult &x : r)
		if (x.mode == BoxMode::kDetect) {
			++detectedNow;
			EXPECT_EQ(x.waited, 2);
		}
	EXPECT_EQ(detectedNow, 1);
	EXPECT_EQ(stream.stats().detected, 3u);
	EXPECT_GE(stream.stats().forced, 1u);
	EXPECT_EQ(stream.stats().maxWait, 2);
}

// A clock that stands still: every stage costs nothing, so the frame's
// plan is its budget less the reserve alone.
class StillClock final : public Clock
{
public:
	int64_t nowNs() const override { return 0; }
};

TEST_F(StreamEstimatorTest, AFrameKeepsAReserveOfItsBudgetForStagesThatRunLong)
{
	StillClock clock;
	PoseEstimator detector({}, &clock);
	TrackerConfig tc;
	tc.detectMinMs = 20;
	const Pose a = test::viewAt(*model_, 37, {-150, -40, 800}), b = test::viewAt(*model_, 12, {0, 60, 800}),
		   c = test::viewAt(*model_, 25, {150, -40, 800});
	const Scene scene = render({a, b, c});
	auto detected = [](const std::vector<StreamResult> &r) {
		return std::count_if(r.begin(), r.end(), [](const StreamResult &x) { return x.mode == BoxMode::kDetect; });
	};
	// 40 ms hold two detections of 20 ms, but not with 5 % kept back.
	StreamEstimator tight(detector, tc, &clock);
	EXPECT_EQ(detected(run(tight, 0, scene, boxesOf(scene), 40)), 1);
	EXPECT_EQ(tight.stats().deferred, 2u);
	// 42.2 ms less 5 % (2.11 ms) hold two.
	StreamEstimator roomy(detector, tc, &clock);
	EXPECT_EQ(detected(run(roomy, 0, scene, boxesOf(scene), 42.2f)), 2);
	EXPECT_EQ(roomy.stats().deferred, 1u);
}

TEST_F(StreamEstimatorTest, SpareTimeInABudgetedFrameDetectsATrackedBoxAgain)
{
	test::StepClock clock(kMs);
	PoseEstimator detector({}, &clock);
	TrackerConfig tc;
	tc.detectMinMs = 20;
	StreamEstimator stream(detector, tc, &clock);
	const Scene s0 = render({moved(start(), 0)});
	run(stream, 0, s0, boxesOf(s0), 500);
	const Scene s1 = render({moved(start(), 1)});
	// Unbudgeted: tracked, nothing more.
	std::vector<StreamResult> r = run(stream, 1, s1, boxesOf(s1));
	EXPECT_EQ(r[0].mode, BoxMode::kTrack);
	EXPECT_EQ(stream.stats().refreshed, 0u);
	// Budgeted with time to spare: detected again, and the better of the
	// two poses kept.
	const Scene s2 = render({moved(start(), 2)});
	r = run(stream, 2, s2, boxesOf(s2), 500);
	EXPECT_EQ(stream.stats().refreshed, 1u);
	ASSERT_TRUE(r[0].estimate.found);
	EXPECT_LT(mm(r[0].estimate.pose, moved(start(), 2)), 5.0);
	// Without refresh, the same frame only tracks.
	TrackerConfig off = tc;
	off.refresh = false;
	StreamEstimator plain(detector, off, &clock);
	run(plain, 0, s0, boxesOf(s0), 500);
	run(plain, 1, s1, boxesOf(s1), 500);
	EXPECT_EQ(plain.stats().refreshed, 0u);
	EXPECT_EQ(plain.stats().tracked, 1u);
}

TEST_F(StreamEstimatorTest, ANewBoxWaitsBehindOneThatWaitedLonger)
{
	test::StepClock clock(kMs);
	PoseEstimator detector({}, &clock);
	TrackerConfig tc;
	tc.detectMinMs = 20;
	StreamEstimator stream(detector, tc, &clock);
	const Pose a = test::viewAt(*model_, 37, {-150, -40, 800}), b = test::viewAt(*model_, 12, {0, 60, 800}),
		   c = test::viewAt(*model_, 25, {150, -40, 800});
	const Scene two = render({a, b});
	std::vector<StreamResult> r = run(stream, 0, two, boxesOf(two), kOneDetectionMs);
	ASSERT_EQ(r[1].mode, BoxMode::kDeferred);
	// A new object appears, listed first: the waiting box goes before it.
	const Scene three = render({a, b, c});
	std::vector<StreamBox> boxes = boxesOf(three);
	r = run(stream, 1, three, {boxes[2], boxes[0], boxes[1]}, kOneDetectionMs);
	EXPECT_EQ(r[0].mode, BoxMode::kDeferred);
	EXPECT_EQ(r[1].mode, BoxMode::kTrack);
	EXPECT_EQ(r[2].mode, BoxMode::kDetect);
}

TEST_F(StreamEstimatorTest, AnObjectMovedElsewhereIsDetectedThereAndItsOldTrackEnds)
{
	PoseEstimator detector;
	TrackerConfig tc;
	tc.maxMissedFrames = 3;
	StreamEstimator stream(detector, tc);
	const Pose here = test::viewAt(*model_, 37, {-120, -20, 800});
	const Pose there = test::viewAt(*model_, 12, {130, 40, 760});
	Scene s = render({here});
	run(stream, 0, s, boxesOf(s));
	run(stream, 1, s, boxesOf(s));
	s = render({there});
	int framesToPose = -1;
	for (int f = 2; f < 8; ++f) {
		const std::vector<StreamResult> r = run(stream, static_cast<uint64_t>(f), s, boxesOf(s));
		if (framesToPose < 0 && r[0].estimate.found && mm(r[0].estimate.pose, there) < 10 &&
		    degrees(r[0].estimate.pose, there) < 10)
			framesToPose = f - 2;
	}
	EXPECT_GE(framesToPose, 0);
	EXPECT_LT(framesToPose, 3);
	EXPECT_EQ(stream.stats().lost, 1u);
	EXPECT_EQ(stream.activeTracks(), 1);
}

TEST_F(StreamEstimatorTest, AnObjectTurnedInPlaceIsDetectedAgainWithinThreeFrames)
{
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	const Pose before = test::viewAt(*model_, 37, {30, -20, 800});
	Scene s = render({before});
	run(stream, 0, s, boxesOf(s));
	run(stream, 1, s, boxesOf(s));
	// Picked up and put back turned, in the same place.
	const Pose after = test::viewAt(*model_, 12, before.t);
	s = render({after});
	int framesToPose = -1;
	for (int f = 2; f < 6; ++f) {
		const std::vector<StreamResult> r = run(stream, static_cast<uint64_t>(f), s, boxesOf(s));
		if (framesToPose < 0 && r[0].estimate.found && mm(r[0].estimate.pose, after) < 10 &&
		    degrees(r[0].estimate.pose, after) < 10)
			framesToPose = f - 2;
	}
	EXPECT_GE(framesToPose, 0);
	EXPECT_LT(framesToPose, 3);
	EXPECT_GE(stream.stats().redetected, 1u);
}

TEST_F(StreamEstimatorTest, ATrackedPoseNotKeptAnswersItsWaitingBoxUnconfirmed)
{
	test::StepClock clock(kMs);
	PoseEstimator detector({}, &clock);
	TrackerConfig tc;
	tc.detectMinMs = 20;
	StreamEstimator stream(detector, tc, &clock);
	const Pose before = test::viewAt(*model_, 37, {30, -20, 800});
	Scene s = render({before});
	std::vector<StreamResult> r = run(stream, 0, s, boxesOf(s), 500);
	ASSERT_EQ(r[0].mode, BoxMode::kDetect);
	ASSERT_TRUE(r[0].estimate.found);
	const float detectedConfidence = r[0].estimate.confidence;
	// Turned in place, and no room for a detection: the tracked pose is
	// not kept, and the box is answered with it, unconfirmed, while its
	// detection waits.
	const Pose after = test::viewAt(*model_, 12, before.t);
	s = render({after});
	r = run(stream, 1, s, boxesOf(s), 1);
	ASSERT_EQ(r[0].mode, BoxMode::kDeferred);
	EXPECT_TRUE(r[0].tracked);
	EXPECT_NE(r[0].verdict, TrackVerdict::kKept);
	EXPECT_TRUE(r[0].provisional);
	ASSERT_TRUE(r[0].estimate.found);
	EXPECT_STREQ(r[0].estimate.reason, "tracked pose not kept, waits for a detection in a later frame");
	EXPECT_LT(r[0].estimate.confidence, detectedConfidence);
	EXPECT_LT(mm(r[0].estimate.pose, before), 0.3 * model().params().diameter);
	EXPECT_EQ(stream.stats().deferred, 1u);
	EXPECT_EQ(stream.stats().provisional, 1u);
	// With room (an unbudgeted frame), the waiting box is detected and
	// placed right.
	r = run(stream, 2, s, boxesOf(s));
	ASSERT_EQ(r[0].mode, BoxMode::kDetect);
	EXPECT_FALSE(r[0].provisional);
	EXPECT_EQ(r[0].waited, 1);
	ASSERT_TRUE(r[0].estimate.found);
	EXPECT_LT(mm(r[0].estimate.pose, after), 10.0);
	EXPECT_LT(degrees(r[0].estimate.pose, after), 10.0);
	// A new box with no track to guess from waits without a pose.
	const Pose other = test::viewAt(*model_, 25, {-150, -40, 800});
	s = render({after, other});
	r = run(stream, 3, s, boxesOf(s), 1);
	ASSERT_EQ(r[1].mode, BoxMode::kDeferred);
	EXPECT_FALSE(r[1].provisional);
	EXPECT_FALSE(r[1].estimate.found);
}

TEST_F(StreamEstimatorTest, BadBoxesGetAStatusAndTheStreamGoesOn)
{
	PoseEstimator detector;
	TrackerConfig tc;
	tc.maxMissedFrames = 2;
	StreamEstimator stream(detector, tc);
	const Pose p = test::viewAt(*model_, 37, {-60, -20, 800});
	const Scene scene = render({p});
	std::vector<StreamBox> boxes = boxesOf(scene);
	run(stream, 0, scene, boxes);
	// The same box twice, a box with no depth, a box outside the image, an
	// object without a model.
	DepthImageMm holed = scene.depth;
	for (int y = 0; y < 40; ++y)
		for (int x = 0; x < 40; ++x)
			holed.at(580 + x, 400 + y) = 0;
	Scene bad{holed, scene.boxes};
	std::vector<StreamBox> frame1{boxes[0], boxes[0], {1, {580, 400, 40, 40}, 0, &model()},
				      {1, {700, 500, 30, 30}, 0, &model()}, {4, {10, 10, 50, 50}, 0, nullptr}};
	std::vector<StreamResult> r = run(stream, 1, bad, frame1);
	EXPECT_EQ(r[0].mode, BoxMode::kTrack);
	EXPECT_EQ(r[1].mode, BoxMode::kDuplicate);
	EXPECT_EQ(r[1].trackId, r[0].trackId);
	EXPECT_FALSE(r[2].estimate.found);
	EXPECT_STREQ(r[2].estimate.reason, "too few valid depth pixels in the box");
	EXPECT_FALSE(r[3].estimate.found);
	EXPECT_STREQ(r[3].estimate.reason, "box outside the image");
	EXPECT_EQ(r[4].mode, BoxMode::kSkipped);
	EXPECT_FALSE(r[4].estimate.found);
	// The object leaves the image: no more boxes; its track ends.
	for (uint64_t f = 2; f < 5; ++f)
		run(stream, f, scene, {});
	EXPECT_EQ(stream.activeTracks(), 0);
	EXPECT_GE(stream.stats().lost, 1u);
	// And the stream goes on: the object back, detected again.
	r = run(stream, 5, scene, boxes);
	EXPECT_EQ(r[0].mode, BoxMode::kDetect);
	EXPECT_TRUE(r[0].estimate.found);
}

TEST_F(StreamEstimatorTest, ATrackWhoseBoxIsMissedCoastsOnItsVelocity)
{
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	const Pose p0 = start();
	for (int f = 0; f < 4; ++f) {
		const Scene s = render({moved(p0, f)});
		run(stream, static_cast<uint64_t>(f), s, boxesOf(s));
	}
	// Frame 4's box is missed; frame 5 is matched by the prediction two
	// frames on and tracked.
	run(stream, 4, render({moved(p0, 4)}), {});
	const Pose truth = moved(p0, 5);
	const Scene s5 = render({truth});
	const std::vector<StreamResult> r = run(stream, 5, s5, boxesOf(s5));
	EXPECT_EQ(r[0].mode, BoxMode::kTrack);
	EXPECT_LT(mm(r[0].estimate.pose, truth), 5.0);
	EXPECT_EQ(stream.stats().started, 1u);
}

} // namespace
} // namespace ihf
