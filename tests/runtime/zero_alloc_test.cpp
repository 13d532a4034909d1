// SPDX-License-Identifier: MIT
// The frame path allocates nothing: 60 frames (the real LM-O frame and a
// synthetic two-object render, alternating), each with several boxes of two
// objects, run through PoseEstimator::estimate (virtual crop, initial
// registration, k = 2 refinement iterations, ICP, one object's comparison
// with its turns about a near-symmetry; half the frames under a
// frame budget so that the cut-short paths run too, and bad boxes for the
// "no pose" paths) while every heap allocation of the process is counted
// (alloc_interpose.h) and Eigen's malloc is forbidden. The count covers the
// libraries as they ship. In the sanitizer build every source has
// EIGEN_RUNTIME_NO_MALLOC and assertions on (CMakeLists.txt), so there a
// hidden Eigen heap allocation aborts at the line that made it. Self-checks
// prove both tripwires fire.

#include <cmath>
#include <type_traits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "core/dataset/bop_dataset.h"
#include "core/estimation/pose_estimator.h"
#include "core/geometry/mesh.h"
#include "core/geometry/rotation.h"
#include "core/model/near_symmetry.h"
#include "core/tracking/stream_estimator.h"
#include "core/training/view_template_builder.h"
#include "core/features/part_extractor.h"
#include "core/features/unit_cube_frame.h"
#include "tests/runtime/alloc_interpose.h"
#include "tests/runtime/small_model.h"

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "this test must be compiled with EIGEN_RUNTIME_NO_MALLOC"
#endif

namespace ihf {
namespace {

struct FrameBox {
	const ObjectModel *model;
	PixelBox box;
};

struct Frame {
	ImageView<const float> depth;
	CameraIntrinsics K;
	std::vector<FrameBox> boxes;
};

PixelBox enlarge(const std::array<int, 4> &b, double f)
{
	const double cx = b[0] + 0.5 * b[2], cy = b[1] + 0.5 * b[3];
	const double w = b[2] * f, h = b[3] * f;
	return {static_cast<int>(std::floor(cx - 0.5 * w)), static_cast<int>(std::floor(cy - 0.5 * h)),
		static_cast<int>(std::ceil(w)), static_cast<int>(std::ceil(h))};
}

PixelBox shifted(PixelBox b, int dx, int dy)
{
	b.x += dx;
	b.y += dy;
	return b;
}

// Keeps the optimiser from eliding an allocation/free pair.
void escape(void *p)
{
	asm volatile("" : : "g"(p) : "memory");
}

template<typename F>
uint64_t allocationsOf(F &&f)
{
	const uint64_t before = test::heapAllocations();
	f();
	return test::heapAllocations() - before;
}

TEST(TripwireSelfCheck, AllocationsInTheWindowAreCounted)
{
	EXPECT_EQ(allocationsOf([] {
			  int *p = new int(3);
			  escape(p);
			  delete p;
		  }),
		  1u);
	EXPECT_EQ(allocationsOf([] {
			  void *p = std::malloc(16);
			  escape(p);
			  std::free(p);
		  }),
		  1u);
	EXPECT_EQ(allocationsOf([] {
			  void *p = std::calloc(4, 4);
			  escape(p);
			  p = std::realloc(p, 4096);
			  escape(p);
			  std::free(p);
		  }),
		  2u);
	EXPECT_EQ(allocationsOf([] {
			  auto *p = new (std::align_val_t(64)) float[4];
			  escape(p);
			  ::operator delete[](p, std::align_val_t(64));
		  }),
		  1u);
	EXPECT_EQ(allocationsOf([] {
			  std::vector<int> v(100);
			  escape(v.data());
		  }),
		  1u);
	EXPECT_EQ(allocationsOf([] {
			  std::string s(100, 'x'); // past the in-place buffer
			  escape(s.data());
		  }),
		  1u);
	int rc = -1;
	EXPECT_EQ(allocationsOf([&rc] {
			  void *p = nullptr;
			  rc = posix_memalign(&p, 64, 256);
			  escape(p);
			  std::free(p);
		  }),
		  1u);
	EXPECT_EQ(rc, 0);
}

TEST(TripwireSelfCheck, EigenHeapAllocationAbortsWhenForbidden)
{
	GTEST_FLAG_SET(death_test_style, "threadsafe");
	EXPECT_DEATH(
		{
			Eigen::internal::set_is_malloc_allowed(false);
			Eigen::MatrixXf m(64, 64);
			m.setZero();
			std::printf("%f\n", m.sum());
		},
		"heap allocation is forbidden");
}

// A writable buffer must not be held by pointer (it would dangle); literals are.
static_assert(!std::is_constructible_v<ErrorText, char (&)[8]>);
static_assert(std::is_constructible_v<ErrorText, const char (&)[8]>);

TEST(ZeroAllocation, FramePathErrorsDoNotAllocate)
{
	// Messages longer than std::string's in-place buffer: before ErrorText
	// each of these failures allocated.
	Status s1 = Status();
	Expected<UnitCubeFrame> f1 = makeError(Errc::kInvalidArgument, "x");
	PartExtractor extractor;
	Expected<Part> p1 = makeError(Errc::kInvalidArgument, "x");
	std::vector<PartCp> out(8);
	const uint64_t n = allocationsOf([&] {
		f1 = makeUnitCubeFrame(std::span<const CloudPoint>{}, 1.0f);
		p1 = extractor.extract(0, PartConfig{}, HocpConfig{}, out);
		s1 = makeError(Errc::kCapacity, "a literal reason well past the in-place buffer");
	});
	EXPECT_EQ(n, 0u);
	ASSERT_FALSE(f1.ok());
	EXPECT_EQ(f1.error().message, "makeUnitCubeFrame: empty cloud");
	EXPECT_TRUE(f1.error().message.isLiteral());
	ASSERT_FALSE(p1.ok());
	EXPECT_NE(p1.error().message.find("before prepare"), std::string::npos);
	ASSERT_FALSE(s1.ok());

	// Offline errors keep owned, composed messages.
	const Error owned = makeError(Errc::kIo, std::string("file ") + "x.ihf" + ": truncated");
	EXPECT_FALSE(owned.message.isLiteral());
	EXPECT_EQ(owned.message, "file x.ihf: truncated");
	EXPECT_EQ("ihf: " + owned.message, "ihf: file x.ihf: truncated");
}

TEST(ZeroAllocation, SixtyFramesThroughTheFullEstimatePath)
{
	test::SmallModel ape = test::trainSmallModel(1, 11);
	test::SmallModel duck = test::trainSmallModel(9, 12);
	ASSERT_TRUE(ape.model && duck.model);
	// View templates for the rotation search, built at start-up as ihf
	// estimate builds them for forests without.
	for (OwnedObjectModel *m : {ape.model.get(), duck.model.get()}) {
		auto pts = buildViewTemplatePoints(m->mesh(), m->params().diameter, {60, 64});
		ASSERT_TRUE(pts.ok());
		m->attachViewTemplates(60, 64, std::move(*pts));
	}
	// The duck taken as nearly symmetric under a half-turn about its z axis,
	// so that its boxes also compare their turns and polish the rivals.
	NearSymmetry halfTurn;
	halfTurn.point = boundingBox(duck.model->mesh()).centre();
	halfTurn.turnDeg = 180;
	halfTurn.differingShare = 0.1f;
	duck.model->setNearSymmetries({halfTurn});

	// The real frame.
	auto dataset = BopDataset::open(test::lmoDir(), "test");
	ASSERT_TRUE(dataset.ok());
	auto scene = dataset->loadScene(2);
	ASSERT_TRUE(scene.ok());
	const SceneCamera &cam = scene->cameras.at(3);
	auto real = dataset->loadDepthMm(2, 3, cam.depthScale);
	ASSERT_TRUE(real.ok());
	CameraIntrinsics realK = cam.intrinsics;
	realK.width = real->width();
	realK.height = real->height();
	PixelBox realApe, realDuck;
	const auto &gt = scene->gt.at(3);
	const auto &info = scene->gtInfo.at(3);
	for (size_t i = 0; i < gt.size(); ++i) {
		if (gt[i].objId == 1)
			realApe = enlarge(info[i].bboxObj, 1.1);
		if (gt[i].objId == 9)
			realDuck = enlarge(info[i].bboxObj, 1.1);
	}
	ASSERT_FALSE(realApe.empty() || realDuck.empty());

	// The synthetic frame: both objects at training-view appearances.
	DepthImageMm synth(640, 480, 0.0f);
	const Pose apeGt = test::viewAt(ape, 37, {-90, 30, 800});
	const Pose duckGt = test::viewAt(duck, 55, {80, -20, 820});
	const PixelBox synthApe = test::renderInto(*ape.model, apeGt, synth);
	const PixelBox synthDuck = test::renderInto(*duck.model, duckGt, synth);

	std::vector<Frame> frames(2);
	frames[0] = {real->view(), realK, {{ape.model.get(), realApe}, {duck.model.get(), realDuck}}};
	frames[1] = {synth.view(), test::kKinect,
		     {{ape.model.get(), synthApe}, {duck.model.get(), synthDuck}}};

	EstimatorLimits limits;
	limits.maxMeshVertices = std::max(ape.model->mesh().vertices.size(), duck.model->mesh().vertices.size());
	limits.threads = 2; // the worker pool's hand-offs allocate nothing either
	PoseEstimator estimator(limits);
	ASSERT_TRUE(estimator.valid());
	EstimatorConfig cfg;
	cfg.iterations = 2;
	cfg.icp = true;
	// Fewer polishes and no half-turns on most frames (the searching frames
	// below run them): the same code as the defaults, in half the time.
	cfg.icpCandidates = 8;
	cfg.halfTurns.candidates = 0;
	cfg.partStride = 8; // fewer parts and votes than the model's 4: a faster test, the same code
	cfg.views.inplane = 0;
	// Every third frame also runs the optional view-template search and
	// half-turns.
	EstimatorConfig searching = cfg;
	searching.views.inplane = 8;
	searching.views.keep = 4;
	searching.halfTurns = HalfTurnConfig{2, 8, 1};
	// Every other one of those renders each half-turn instead of screening
	// them on the templates.
	EstimatorConfig rendering = searching;
	rendering.halfTurns.screen = 0;

	// 60 frames: one whole period of the patterns below (real or synthetic
	// frame, budget, searching or rendering profile, box shift), so every
	// combination of them runs once inside the counted window.
	constexpr int kWarmUp = 4, kFrames = 60;
	int found = 0, noPose = 0, synthApeGood = 0, synthApeBoxes = 0, budgetStops = 0, icpRuns = 0;
	uint64_t windowStart = 0;
	for (int f = 0; f < kWarmUp + kFrames; ++f) {
		if (f == kWarmUp) {
			windowStart = test::heapAllocations();
			Eigen::internal::set_is_malloc_allowed(false);
		}
		const Frame &frame = frames[f % 2];
		const int dx = f % 5 - 2, dy = (f / 5) % 3 - 1;
		// Half the frames unlimited, half under a tight budget.
		const float budget = f % 4 < 2 ? 0.0f : 60.0f;
		estimator.beginFrame(static_cast<int>(frame.boxes.size()) + 1, budget);
		for (size_t b = 0; b < frame.boxes.size(); ++b) {
			const FrameBox &fb = frame.boxes[b];
			PoseEstimate e = estimator.estimate(frame.depth, frame.K, shifted(fb.box, dx, dy), *fb.model,
							    f % 6 == 0 ? searching : f % 3 == 0 ? rendering : cfg);
			found += e.found;
			noPose += !e.found;
			budgetStops += e.budgetStopped;
			icpRuns += e.icpApplied;
			if (f % 2 == 1 && b == 0) {
				++synthApeBoxes;
				synthApeGood += e.found && (e.pose.t - apeGt.t).norm() < 20.0;
			}
		}
		// Bad boxes: outside the image, and one with no depth in it.
		PoseEstimate outside = estimator.estimate(frame.depth, frame.K, PixelBox{700, 10, 40, 40},
							  *ape.model, cfg);
		PoseEstimate sparse = estimator.estimate(frame.depth, frame.K, PixelBox{0, 0, 5, 5}, *duck.model, cfg);
		noPose += !outside.found + !sparse.found;
		estimator.endFrame();
	}
	Eigen::internal::set_is_malloc_allowed(true);
	const uint64_t allocations = test::heapAllocations() - windowStart;

	EXPECT_EQ(allocations, 0u) << "heap allocations in " << kFrames << " frames";
	// The loop really did the work it claims to.
	const int boxes = (kWarmUp + kFrames) * 2;
	EXPECT_GE(found, boxes * 8 / 10);
	EXPECT_GE(noPose, 2 * (kWarmUp + kFrames));
	EXPECT_GE(synthApeGood, synthApeBoxes * 8 / 10);
	EXPECT_GT(icpRuns, 0);
	EstimatorStats s = estimator.stats();
	EXPECT_EQ(s.frames, static_cast<uint64_t>(kWarmUp + kFrames));
	EXPECT_GE(s.iterations, static_cast<uint64_t>(kFrames));
	EXPECT_GT(s.stages[static_cast<int>(Stage::kViews)].calls, 0u);
	EXPECT_GT(s.stages[static_cast<int>(Stage::kHalfTurns)].calls, 0u);
	EXPECT_GT(s.stages[static_cast<int>(Stage::kSymmetryTurns)].calls, 0u);
	// A budgeted frame's first box has a third of 60 ms: the tight profile.
	EXPECT_GT(s.tightBoxes, 0u);
	std::printf("frames %d, boxes found %d, no pose %d, budget stops %d, arena used %zu of %zu bytes\n",
		    kWarmUp + kFrames, found, noPose, budgetStops, s.arenaHighWater, s.arenaCapacity);
	for (int i = 0; i < kStageCount; ++i)
		std::printf("  %-13s %8.1f ms in %llu calls\n", stageName(static_cast<Stage>(i)),
			    1e-6 * static_cast<double>(s.stages[i].totalNs),
			    static_cast<unsigned long long>(s.stages[i].calls));
}

// Tracking: a stream of moving objects, tracked from frame to frame, with
// detections (the first frames, a box that appears, an object turned in
// place), deferred detections in budgeted frames, a duplicate box, a box
// without depth and frames without boxes; nothing allocates.
TEST(ZeroAllocation, StreamOfTrackedFramesAllocatesNothing)
{
	test::SmallModel ape = test::trainSmallModel(1, 11, 20, 2);
	ASSERT_TRUE(ape.model);
	auto pts = buildViewTemplatePoints(ape.model->mesh(), ape.model->params().diameter, {40, 32});
	ASSERT_TRUE(pts.ok());
	ape.model->attachViewTemplates(40, 32, std::move(*pts));

	constexpr int kWarmUp = 3, kFrames = 40;
	const Pose a0 = test::viewAt(ape, 37, {-100, -20, 800}), b0 = test::viewAt(ape, 12, {110, 40, 780});
	struct StreamFrame {
		DepthImageMm depth{640, 480, 0.0f};
		std::vector<StreamBox> boxes;
	};
	// Rendered before the window: the frames themselves are the sensor's.
	std::vector<StreamFrame> frames(kWarmUp + kFrames);
	for (int f = 0; f < kWarmUp + kFrames; ++f) {
		StreamFrame &fr = frames[static_cast<size_t>(f)];
		const double turn = (f == 25 ? 150.0 : 0.0) + 1.0 * f;
		Pose a = a0;
		a.R = Eigen::AngleAxisd(turn * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix() * a0.R;
		a.t += Eigen::Vector3d(2.0, 1.0, 0.0) * f;
		Pose b = b0;
		b.t += Eigen::Vector3d(-1.5, 0.5, 1.0) * f;
		const PixelBox boxA = test::renderInto(*ape.model, a, fr.depth);
		const PixelBox boxB = test::renderInto(*ape.model, b, fr.depth);
		for (float &d : std::span<float>(fr.depth.view().data, 640 * 480))
			d = d > 0 ? d : 1000.0f;
		if (f % 10 == 7)
			continue; // the detector saw nothing
		fr.boxes.push_back({1, boxA, 0, ape.model.get()});
		if (f >= 5)
			fr.boxes.push_back({1, boxB, 0, ape.model.get()}); // appears at frame 5
		if (f % 6 == 0)
			fr.boxes.push_back({1, boxA, 0, ape.model.get()}); // repeated
		if (f % 9 == 0)
			fr.boxes.push_back({1, PixelBox{0, 0, 4, 4}, 0, ape.model.get()}); // no depth
	}

	EstimatorLimits limits;
	limits.maxMeshVertices = ape.model->mesh().vertices.size();
	PoseEstimator estimator(limits);
	ASSERT_TRUE(estimator.valid());
	StreamEstimator stream(estimator, TrackerConfig{});
	ASSERT_TRUE(stream.valid());
	EstimatorConfig cfg;
	cfg.iterations = 1;
	cfg.icpCandidates = 4;
	cfg.halfTurns.candidates = 0;
	cfg.partStride = 8;
	std::array<StreamResult, 8> results;
	uint64_t windowStart = 0;
	for (int f = 0; f < kWarmUp + kFrames; ++f) {
		if (f == kWarmUp) {
			windowStart = test::heapAllocations();
			Eigen::internal::set_is_malloc_allowed(false);
		}
		const StreamFrame &fr = frames[static_cast<size_t>(f)];
		// Some frames inside a budget too short for every detection.
		const float budget = f % 4 == 3 ? 15.0f : 0.0f;
		stream.estimateFrame(static_cast<uint64_t>(f), fr.depth.view(), test::kKinect, fr.boxes, cfg, budget,
				     std::span<StreamResult>(results.data(), fr.boxes.size()));
	}
	Eigen::internal::set_is_malloc_allowed(true);
	const uint64_t allocations = test::heapAllocations() - windowStart;
	EXPECT_EQ(allocations, 0u) << "heap allocations in " << kFrames << " tracked frames";
	const TrackingStats &t = stream.stats();
	EXPECT_GT(t.tracked, static_cast<uint64_t>(kFrames));
	EXPECT_GE(t.detected, 3u);
	EXPECT_GT(t.duplicates, 0u);
	std::printf("tracked %llu detected %llu re-detected %llu deferred %llu duplicates %llu lost %llu\n",
		    static_cast<unsigned long long>(t.tracked), static_cast<unsigned long long>(t.detected),
		    static_cast<unsigned long long>(t.redetected), static_cast<unsigned long long>(t.deferred),
		    static_cast<unsigned long long>(t.duplicates), static_cast<unsigned long long>(t.lost));
}

} // namespace
} // namespace ihf
