// SPDX-License-Identifier: MIT
// Synthetic sequences from the LM-O meshes (the three smallest, a half-size
// camera): the ground truth agrees with the rendered and the sensor depth,
// the detector's boxes hold the visible objects and come for every visible
// target, a moved object rests, travels and rests again, targets hide each
// other, and frames are deterministic.

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "core/render/depth_renderer.h"
#include "core/synth/model_library.h"
#include "core/synth/sequence_synthesizer.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

const std::vector<int> kObjects = {1, 9, 11};

std::vector<uint16_t> pixels(const DepthImage16 &image)
{
	const auto p = image.pixels();
	return {p.begin(), p.end()};
}


CameraIntrinsics halfKinect()
{
	CameraIntrinsics K = kinectV1Intrinsics();
	K.fx /= 2;
	K.fy /= 2;
	K.cx /= 2;
	K.cy /= 2;
	K.width /= 2;
	K.height /= 2;
	return K;
}

class SynthSequence : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		auto lib = ModelLibrary::load(test::lmoDir() / "models", kObjects);
		ASSERT_TRUE(lib) << lib.error().message;
		library_ = new ModelLibrary(std::move(*lib));
	}
	static void TearDownTestSuite()
	{
		delete library_;
		library_ = nullptr;
	}

	static SequenceParams params(uint64_t seed, int frames = 60)
	{
		SequenceParams p;
		p.synth.seed = seed;
		p.frames = frames;
		p.perFrameMin = p.perFrameMax = 3;
		p.changeProbability = 0; // the move only
		p.detector.missProbability = 0;
		p.keepClean = true;
		return p;
	}

	static ModelLibrary *library_;
	const CameraIntrinsics K_ = halfKinect();
};

ModelLibrary *SynthSequence::library_ = nullptr;

TEST_F(SynthSequence, GroundTruthAgreesWithTheDepthAndBoxesHoldTheVisibleObjects)
{
	SequenceSynthesizer synth(*library_, K_, params(2, 40), kObjects);
	auto scene = synth.plan(1);
	ASSERT_TRUE(scene) << scene.error().message;
	ASSERT_EQ(scene->targets.size(), 3u);
	DepthRenderer renderer(library_->maxVertices());
	const KinectParams &kp = synth.params().synth.sensor;
	int instances = 0, centres = 0, partlyHidden = 0;
	for (int f = 0; f < 40; f += 3) {
		auto frame = synth.frame(*scene, f);
		ASSERT_TRUE(frame) << frame.error().message;
		ASSERT_EQ(frame->gt.size(), frame->info.size());
		std::set<int> boxed;
		for (const Detection &d : frame->detections) {
			EXPECT_EQ(d.sceneId, 1);
			EXPECT_EQ(d.imageId, f);
			EXPECT_TRUE(boxed.insert(d.categoryId).second) << "two boxes for one object";
		}
		for (size_t k = 0; k < frame->gt.size(); ++k) {
			SCOPED_TRACE("frame " + std::to_string(f) + " object " + std::to_string(frame->gt[k].objId));
			const GtInstance &gt = frame->gt[k];
			const GtInfo &info = frame->info[k];
			const uint16_t label = frame->gtLabel[k];
			ASSERT_GT(info.pxCountVisib, 0);
			++instances;
			partlyHidden += info.visibFract > 0.05 && info.visibFract < 0.9;
			// The written pose renders exactly onto the scene's visible
			// pixels of the object.
			DepthImageMm alone(K_.width, K_.height, 0.0f);
			ASSERT_TRUE(renderer.render(*library_->model(gt.objId).mesh, gt.pose, K_, alone.view()));
			int visible = 0, agree = 0;
			std::vector<double> sensorError;
			double cx = 0, cy = 0;
			for (int y = 0; y < K_.height; ++y) {
				for (int x = 0; x < K_.width; ++x) {
					if (frame->cleanLabel.at(x, y) != label)
						continue;
					++visible;
					cx += x;
					cy += y;
					agree += std::abs(alone.at(x, y) - frame->cleanDepth.at(x, y)) < 0.01f;
					if (frame->depth.at(x, y) > 0)
						sensorError.push_back(std::abs(frame->depth.at(x, y) - alone.at(x, y)));
				}
			}
			EXPECT_EQ(visible, info.pxCountVisib);
			EXPECT_EQ(agree, visible);
			// The sensor's depth over the object: the pose's surface plus
			// the Kinect's noise and steps (a few mm at ~1 m).
			if (sensorError.size() > 30) {
				std::nth_element(sensorError.begin(), sensorError.begin() + sensorError.size() / 2,
						 sensorError.end());
				EXPECT_LT(sensorError[sensorError.size() / 2], 4.0);
			}
			// At the projected centre of its visible part, when that pixel
			// is the object's and 3 px away from its outline, the sensor
			// agrees with the pose within 5 sigma and a step (the Kinect
			// moves depth sideways by up to 2 px: some pose depth within
			// 2 px must match).
			const int px = static_cast<int>(std::lround(cx / visible)), py = static_cast<int>(std::lround(cy / visible));
			bool interior = px >= 3 && py >= 3 && px < K_.width - 3 && py < K_.height - 3;
			for (int dy = -3; dy <= 3 && interior; ++dy)
				for (int dx = -3; dx <= 3 && interior; ++dx)
					interior = frame->cleanLabel.at(px + dx, py + dy) == label;
			if (interior && frame->depth.at(px, py) > 0) {
				const double z = alone.at(px, py);
				double best = 1e9;
				for (int dy = -2; dy <= 2; ++dy)
					for (int dx = -2; dx <= 2; ++dx)
						best = std::min(best, std::abs(frame->depth.at(px, py) -
									       static_cast<double>(alone.at(px + dx, py + dy))));
				EXPECT_LE(best, 5 * kinectAxialSigmaMm(kp, z, 1.2) + kinectDepthStep(kp, z) + 1.0);
				++centres;
			}

			// One box per target at least 10 % visible (no misses asked),
			// holding the object's visible pixels.
			const Detection *box = nullptr;
			for (const Detection &d : frame->detections)
				if (d.categoryId == gt.objId)
					box = &d;
			if (info.visibFract < 0.1) {
				EXPECT_EQ(box, nullptr);
				continue;
			}
			ASSERT_NE(box, nullptr);
			int inside = 0;
			for (int y = 0; y < K_.height; ++y)
				for (int x = 0; x < K_.width; ++x)
					inside += frame->cleanLabel.at(x, y) == label && x >= box->bbox[0] &&
						  x <= box->bbox[0] + box->bbox[2] && y >= box->bbox[1] &&
						  y <= box->bbox[1] + box->bbox[3];
			EXPECT_GE(inside, 0.7 * visible);
		}
		// Boxes only for listed (visible) objects.
		for (int id : boxed) {
			bool listed = false;
			for (const GtInstance &g : frame->gt)
				listed = listed || g.objId == id;
			EXPECT_TRUE(listed) << id;
		}
	}
	EXPECT_GT(instances, 20);
	EXPECT_GT(centres, 10);
	// Standing close together, they hide each other (or the border cuts them).
	EXPECT_GT(partlyHidden, 0);
}

TEST_F(SynthSequence, AMovedObjectRestsTravelsAndRestsAgain)
{
	const int frames = 60;
	SequenceSynthesizer synth(*library_, K_, params(5, frames), kObjects);
	auto scene = synth.plan(1);
	ASSERT_TRUE(scene) << scene.error().message;
	const TargetSlot *moved = nullptr;
	for (const TargetSlot &t : scene->targets) {
		EXPECT_LE(t.schedule.carries().size(), 1u);
		if (!t.schedule.carries().empty())
			moved = &t;
	}
	ASSERT_NE(moved, nullptr);
	const Carry &carry = moved->schedule.carries()[0];
	ASSERT_EQ(carry.kind, CarryKind::kMove);
	EXPECT_GE(carry.start, 0.1 * frames / 30.0);
	EXPECT_LE(carry.end, 0.9 * frames / 30.0 + 1e-9);
	// Its new place is elsewhere on the table.
	EXPECT_GT((carry.to.t - carry.from.t).head<2>().norm(), 80.0);
	EXPECT_NEAR(carry.to.t.z(), carry.from.t.z(), 1e-9);

	// The pose in the world, from the written ground truth and the camera.
	std::vector<Pose> before, during, after;
	for (int f = 0; f < frames; f += 2) {
		auto frame = synth.frame(*scene, f);
		ASSERT_TRUE(frame) << frame.error().message;
		for (const GtInstance &g : frame->gt) {
			if (g.objId != moved->objId)
				continue;
			const Pose world = frame->worldToCamera.inverse() * g.pose;
			const double t = f / 30.0;
			(t < carry.start ? before : t >= carry.end ? after : during).push_back(world);
		}
	}
	ASSERT_GE(before.size(), 2u);
	ASSERT_GE(after.size(), 2u);
	for (const auto *rest : {&before, &after}) {
		for (const Pose &p : *rest) {
			EXPECT_LT((p.t - rest->front().t).norm(), 1e-6);
			EXPECT_LT(rotationAngle(p.R, rest->front().R), 1e-6);
		}
	}
	EXPECT_LT((before.front().t - carry.from.t).norm(), 1e-6);
	EXPECT_LT((after.front().t - carry.to.t).norm(), 1e-6);
	for (const Pose &p : during) {
		EXPECT_GT((p.t - carry.from.t).norm() + (p.t - carry.to.t).norm(), 1.0);
		EXPECT_GE(p.t.z(), carry.from.t.z() - 1e-9); // never below the table
	}
}

TEST_F(SynthSequence, FramesAreDeterministicAndIndependentOfOrder)
{
	SequenceParams p = params(9, 30);
	p.keepClean = false;
	p.detector.missProbability = 0.3;
	SequenceSynthesizer a(*library_, K_, p, kObjects), b(*library_, K_, p, kObjects);
	auto sa = a.plan(2), sb = b.plan(2);
	ASSERT_TRUE(sa && sb);
	// b renders frame 20 first: a frame draws from its own stream.
	auto b20 = b.frame(*sb, 20);
	auto a7 = a.frame(*sa, 7), a20 = a.frame(*sa, 20), b7 = b.frame(*sb, 7);
	ASSERT_TRUE(a7 && a20 && b7 && b20);
	EXPECT_EQ(pixels(a7->depth), pixels(b7->depth));
	EXPECT_EQ(pixels(a20->depth), pixels(b20->depth));
	ASSERT_EQ(a20->gt.size(), b20->gt.size());
	for (size_t k = 0; k < a20->gt.size(); ++k) {
		EXPECT_EQ(a20->gt[k].objId, b20->gt[k].objId);
		EXPECT_EQ(a20->gt[k].pose.t, b20->gt[k].pose.t);
	}
	ASSERT_EQ(a20->detections.size(), b20->detections.size());
	for (size_t k = 0; k < a20->detections.size(); ++k)
		EXPECT_EQ(a20->detections[k].bbox, b20->detections[k].bbox);
	EXPECT_NE(pixels(a7->depth), pixels(a20->depth));
	// Another sequence is another table.
	auto other = a.plan(3);
	ASSERT_TRUE(other);
	EXPECT_NE(other->layout.objects[0].modelToWorld.t, sa->layout.objects[0].modelToWorld.t);
}

TEST_F(SynthSequence, TakingAwayAndPuttingDownKeepTheCountInRange)
{
	SequenceParams p = params(1, 90);
	p.keepClean = false;
	p.changeProbability = 1;
	p.perFrameMin = 2;
	p.perFrameMax = 3;
	SequenceSynthesizer synth(*library_, K_, p, kObjects);
	int away = 0, down = 0;
	for (int seq = 1; seq <= 6; ++seq) {
		auto scene = synth.plan(seq);
		ASSERT_TRUE(scene) << scene.error().message;
		int moves = 0;
		for (const TargetSlot &t : scene->targets) {
			for (const Carry &c : t.schedule.carries()) {
				moves += c.kind == CarryKind::kMove;
				away += c.kind == CarryKind::kTakeAway;
				down += c.kind == CarryKind::kPutDown;
			}
		}
		EXPECT_EQ(moves, 1);
		for (int f = 0; f < p.frames; ++f) {
			int present = 0;
			for (const TargetSlot &t : scene->targets)
				present += t.schedule.present(f / p.fps);
			EXPECT_GE(present, 2);
			EXPECT_LE(present, 3);
		}
	}
	EXPECT_GT(away, 0);
	EXPECT_GT(down, 0);
}

} // namespace
} // namespace ihf
