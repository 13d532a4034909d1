// SPDX-License-Identifier: MIT
// The per-frame path shared by ihf estimate and ihf run
// (firmware_app/runtime/frame_estimator.h, built by pose_pipeline.h): every
// box answered once, in the order given, cold or tracked; a box whose
// object has no forest answered without a pose; a sink's error stops the
// frame; a frame without boxes ages the tracks.

#include <vector>

#include <gtest/gtest.h>

#include "firmware_app/runtime/pose_pipeline.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

constexpr int kObject = 7;

struct Answer {
	int objId;
	bool hasModel;
	BoxMode mode;
	std::string reason;
};

class RecordingSink : public BoxSink
{
public:
	Status onBox(const FrameBox &box, const ObjectModel *model, const StreamResult &r) override
	{
		answers.push_back({box.objId, model != nullptr, r.mode, r.estimate.reason});
		if (failAfter >= 0 && static_cast<int>(answers.size()) > failAfter)
			return makeError(Errc::kIo, "the sink is full");
		return {};
	}
	std::vector<Answer> answers;
	int failAfter = -1; // fail on the answer after this many (-1: never)
};

// A wall 700 mm away, 160 x 120 pixels.
struct Wall {
	Image<float> depth{160, 120, 700.0f};
	CameraIntrinsics K{200, 200, 80, 60, 160, 120};
};

std::unique_ptr<PosePipeline> pipeline(EstimateSettings &settings, const TrackerConfig *tracking, PacingClock &clock)
{
	settings.estimator.iterations = 0;
	auto p = PosePipeline::create({{kObject, test::goldenForest()}}, settings, tracking, clock, "test");
	EXPECT_TRUE(p) << (p ? "" : p.error().message);
	return p ? std::move(p.value()) : nullptr;
}

const std::vector<FrameBox> kBoxes = {
	{kObject, {40, 30, 40, 40}, 0},
	{99, {10, 10, 20, 20}, 0},
	{kObject, {100, 60, 40, 40}, 0},
};

TEST(FrameEstimator, ColdBoxesAreAnsweredInOrder)
{
	EstimateSettings settings;
	SteadyPacingClock clock;
	auto p = pipeline(settings, nullptr, clock);
	ASSERT_TRUE(p);
	EXPECT_EQ(p->tracker(), nullptr);
	Wall f;
	RecordingSink sink;
	ASSERT_TRUE(p->frames().estimate(0, f.depth.view(), f.K, kBoxes, sink).ok());
	ASSERT_EQ(sink.answers.size(), 3u);
	EXPECT_EQ(sink.answers[0].objId, kObject);
	EXPECT_TRUE(sink.answers[0].hasModel);
	EXPECT_EQ(sink.answers[0].mode, BoxMode::kDetect);
	EXPECT_EQ(sink.answers[1].objId, 99);
	EXPECT_FALSE(sink.answers[1].hasModel);
	EXPECT_EQ(sink.answers[1].mode, BoxMode::kSkipped);
	EXPECT_NE(sink.answers[1].reason.find("no forest"), std::string::npos) << sink.answers[1].reason;
	EXPECT_EQ(sink.answers[2].objId, kObject);
	EXPECT_EQ(sink.answers[2].mode, BoxMode::kDetect);
}

TEST(FrameEstimator, TrackedBoxesAreAnsweredInOrder)
{
	EstimateSettings settings;
	SteadyPacingClock clock;
	const TrackerConfig tracking;
	auto p = pipeline(settings, &tracking, clock);
	ASSERT_TRUE(p);
	ASSERT_NE(p->tracker(), nullptr);
	Wall f;
	RecordingSink sink;
	ASSERT_TRUE(p->frames().estimate(0, f.depth.view(), f.K, kBoxes, sink).ok());
	ASSERT_EQ(sink.answers.size(), 3u);
	EXPECT_EQ(sink.answers[0].objId, kObject);
	EXPECT_TRUE(sink.answers[0].hasModel);
	EXPECT_NE(sink.answers[0].mode, BoxMode::kSkipped);
	EXPECT_FALSE(sink.answers[1].hasModel);
	EXPECT_EQ(sink.answers[1].mode, BoxMode::kSkipped);
	EXPECT_EQ(sink.answers[2].objId, kObject);
	EXPECT_NE(sink.answers[2].mode, BoxMode::kSkipped);
	// The box without a forest is not the tracker's.
	EXPECT_EQ(p->tracker()->stats().boxes, 2u);
	EXPECT_EQ(p->tracker()->stats().frames, 1u);
}

TEST(FrameEstimator, AFrameWithoutBoxesAgesTheTracks)
{
	EstimateSettings settings;
	SteadyPacingClock clock;
	const TrackerConfig tracking;
	auto p = pipeline(settings, &tracking, clock);
	ASSERT_TRUE(p);
	Wall f;
	p->frames().skipFrame(0, f.K);
	p->frames().skipFrame(1, f.K);
	EXPECT_EQ(p->tracker()->stats().frames, 2u);
	EXPECT_EQ(p->tracker()->stats().boxes, 0u);
}

TEST(FrameEstimator, ASinkErrorStopsTheFrame)
{
	for (const bool tracked : {false, true}) {
		EstimateSettings settings;
		SteadyPacingClock clock;
		const TrackerConfig tracking;
		auto p = pipeline(settings, tracked ? &tracking : nullptr, clock);
		ASSERT_TRUE(p);
		Wall f;
		RecordingSink sink;
		sink.failAfter = 1;
		const Status st = p->frames().estimate(0, f.depth.view(), f.K, kBoxes, sink);
		ASSERT_FALSE(st.ok()) << (tracked ? "tracked" : "cold");
		EXPECT_EQ(st.error().message.view(), "the sink is full");
		EXPECT_EQ(sink.answers.size(), 2u) << (tracked ? "tracked" : "cold");
	}
}

TEST(PosePipeline, AMissingForestIsRefusedByName)
{
	EstimateSettings settings;
	SteadyPacingClock clock;
	const std::filesystem::path missing = std::filesystem::temp_directory_path() / "ihf_no_such_forest.ihf";
	auto p = PosePipeline::create({{1, missing}}, settings, nullptr, clock, "test");
	ASSERT_FALSE(p);
	EXPECT_NE(p.error().message.find("ihf_no_such_forest.ihf"), std::string::npos) << p.error().message;
}

} // namespace
} // namespace ihf::app
