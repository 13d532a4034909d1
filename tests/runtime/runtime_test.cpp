// SPDX-License-Identifier: MIT
// The runtime building blocks on their own: arena, stage timer, cost model
// and frame budget, all with a clock the test drives.

#include <cstdint>

#include <gtest/gtest.h>

#include "core/runtime/arena.h"
#include "core/runtime/frame_budget.h"
#include "core/runtime/stage_timer.h"

namespace ihf {
namespace {

class ManualClock final : public Clock
{
public:
	int64_t nowNs() const override { return t; }
	int64_t t = 0;
};

struct Wide {
	double a[5]; // 40 bytes: rounds up to one 64-byte block
};

TEST(Arena, AllocationsAreAlignedAndCounted)
{
	auto arena = Arena::create(1000);
	ASSERT_TRUE(arena.ok());
	EXPECT_EQ(arena->capacity(), 1024u); // rounded up to the alignment
	auto a = arena->allocate<uint8_t>(1);
	auto b = arena->allocate<Wide>(3);
	ASSERT_TRUE(a.ok() && b.ok());
	EXPECT_EQ(a->size(), 1u);
	EXPECT_EQ(b->size(), 3u);
	EXPECT_EQ(reinterpret_cast<uintptr_t>(a->data()) % Arena::kAlignment, 0u);
	EXPECT_EQ(reinterpret_cast<uintptr_t>(b->data()) % Arena::kAlignment, 0u);
	EXPECT_EQ(reinterpret_cast<uint8_t *>(b->data()) - a->data(), 64);
	EXPECT_EQ(arena->used(), 64u + 128u); // three Wides: 120 bytes -> 128
}

TEST(Arena, FullArenaGivesAnErrorNotAThrow)
{
	auto arena = Arena::create(256);
	ASSERT_TRUE(arena.ok());
	ASSERT_TRUE(arena->allocate<float>(48).ok()); // 192 bytes
	auto tooBig = arena->allocate<float>(17);     // 68 -> 128 bytes, 64 left
	ASSERT_FALSE(tooBig.ok());
	EXPECT_EQ(tooBig.error().code, Errc::kCapacity);
	EXPECT_EQ(arena->used(), 192u); // a failed allocation takes nothing
	EXPECT_TRUE(arena->allocate<float>(16).ok());
	EXPECT_FALSE(arena->allocate<float>(1).ok());
	// A count whose byte size overflows is refused too.
	EXPECT_FALSE(arena->allocate<double>(SIZE_MAX / 4).ok());

	Arena empty;
	EXPECT_FALSE(empty.allocate<int>(1).ok());
	EXPECT_TRUE(empty.allocate<int>(0).ok());
}

TEST(Arena, ScopesReleaseScratchAndTheHighWaterMarkRemembers)
{
	auto arena = Arena::create(4096);
	ASSERT_TRUE(arena.ok());
	ASSERT_TRUE(arena->allocate<uint8_t>(100).ok()); // persistent: 128
	{
		ArenaScope scope(*arena);
		ASSERT_TRUE(arena->allocate<uint8_t>(1000).ok()); // 1024
		EXPECT_EQ(arena->used(), 1152u);
	}
	EXPECT_EQ(arena->used(), 128u);
	{
		ArenaScope scope(*arena);
		ASSERT_TRUE(arena->allocate<uint8_t>(10).ok());
	}
	EXPECT_EQ(arena->used(), 128u);
	EXPECT_EQ(arena->highWater(), 1152u);
}

TEST(Arena, SizerMatchesWhatTheArenaTakes)
{
	ArenaSizer sizer;
	std::span<float> f;
	std::span<Wide> w;
	std::span<uint8_t> u;
	ASSERT_TRUE(arenaTake(sizer, f, 1001) && arenaTake(sizer, w, 7) && arenaTake(sizer, u, 65));
	EXPECT_TRUE(f.empty() && w.empty() && u.empty());

	auto arena = Arena::create(sizer.bytes);
	ASSERT_TRUE(arena.ok());
	ASSERT_TRUE(arenaTake(*arena, f, 1001) && arenaTake(*arena, w, 7) && arenaTake(*arena, u, 65));
	EXPECT_EQ(arena->used(), sizer.bytes);
	EXPECT_EQ(arena->remaining(), 0u);
	EXPECT_EQ(f.size(), 1001u);
	EXPECT_FALSE(arenaTake(*arena, u, 1));
}

TEST(Arena, MovingKeepsTheBlock)
{
	auto arena = Arena::create(128);
	ASSERT_TRUE(arena.ok());
	auto s = arena->allocate<int>(4);
	ASSERT_TRUE(s.ok());
	(*s)[0] = 42;
	Arena moved = std::move(*arena);
	EXPECT_EQ(moved.used(), 64u);
	EXPECT_EQ(arena->capacity(), 0u);
	EXPECT_EQ((*s)[0], 42); // spans stay valid: the block did not move
}

TEST(StageTimer, LapsChargeTheTimeSinceTheLastLap)
{
	ManualClock clock;
	StageTimer timer(clock);
	clock.t = 100;
	timer.start();
	clock.t = 130;
	EXPECT_EQ(timer.lap(Stage::kCrop), 130);
	clock.t = 200;
	EXPECT_EQ(timer.now(), 200); // a read charges nothing
	clock.t = 210;
	timer.lap(Stage::kCloud);
	clock.t = 215;
	timer.lap(Stage::kCloud);
	const auto &c = timer.counters();
	EXPECT_EQ(c[static_cast<int>(Stage::kCrop)].totalNs, 30);
	EXPECT_EQ(c[static_cast<int>(Stage::kCloud)].totalNs, 85);
	EXPECT_EQ(c[static_cast<int>(Stage::kCloud)].calls, 2u);
	EXPECT_EQ(c[static_cast<int>(Stage::kCloud)].maxNs, 80);
	EXPECT_EQ(c[static_cast<int>(Stage::kIcp)].calls, 0u);
	EXPECT_EQ(timer.last(), 215);
}

// A stage resumed inside another's call (the ICP inside the half-turns)
// adds its time without a call; its call's length, for the maximum, is all
// of it.
TEST(StageTimer, ResumedTimeCountsTowardsTheCallNotTheCalls)
{
	ManualClock clock;
	StageTimer timer(clock);
	clock.t = 0;
	timer.start();
	clock.t = 40;
	timer.resume(Stage::kHalfTurns); // 40 of half-turns
	clock.t = 50;
	timer.lap(Stage::kCloud);        // 10 of cloud, a call
	clock.t = 80;
	timer.resume(Stage::kIcp);       // 30 of ICP, no call
	clock.t = 85;
	timer.lap(Stage::kHalfTurns);    // 5 more: the half-turns' call is 45
	const auto &c = timer.counters();
	EXPECT_EQ(c[static_cast<int>(Stage::kHalfTurns)].calls, 1u);
	EXPECT_EQ(c[static_cast<int>(Stage::kHalfTurns)].totalNs, 45);
	EXPECT_EQ(c[static_cast<int>(Stage::kHalfTurns)].maxNs, 45);
	EXPECT_EQ(c[static_cast<int>(Stage::kIcp)].calls, 0u);
	EXPECT_EQ(c[static_cast<int>(Stage::kIcp)].totalNs, 30);
	EXPECT_EQ(c[static_cast<int>(Stage::kCloud)].calls, 1u);
	clock.t = 95;
	timer.lap(Stage::kHalfTurns); // a new call of 10: the resumed time is spent
	EXPECT_EQ(c[static_cast<int>(Stage::kHalfTurns)].maxNs, 45);
	EXPECT_EQ(c[static_cast<int>(Stage::kHalfTurns)].totalNs, 55);
}

TEST(StageCostModel, RunningAveragePerStage)
{
	StageCostModel model(0.5);
	EXPECT_EQ(model.predict({Stage::kIbsFit}), 0); // nothing seen yet
	StageTotals a{}, b{};
	b[static_cast<int>(Stage::kIbsFit)] = 1000;
	b[static_cast<int>(Stage::kForest)] = 400;
	model.observe(a, b); // the first observation is taken as is
	EXPECT_EQ(model.predict({Stage::kIbsFit, Stage::kForest}), 1400);
	StageTotals c = b;
	c[static_cast<int>(Stage::kIbsFit)] += 2000; // this iteration: 2000
	model.observe(b, c);                          // forest did not run: unchanged
	EXPECT_EQ(model.average(Stage::kIbsFit), 1500);
	EXPECT_EQ(model.average(Stage::kForest), 400);
}

TEST(StageCostModel, BoundAddsTheRunningDeviation)
{
	StageCostModel model(0.5);
	EXPECT_EQ(model.bound(Stage::kIcp, 2.0), 0); // nothing seen yet
	model.observe(Stage::kIcp, 1000);
	EXPECT_EQ(model.bound(Stage::kIcp, 0.0), 1000);
	EXPECT_EQ(model.bound(Stage::kIcp, 2.0), 1500); // spread: a quarter of the first cost
	model.observe(Stage::kIcp, 2000);                // 1000 above the average
	EXPECT_EQ(model.average(Stage::kIcp), 1500);
	EXPECT_EQ(model.bound(Stage::kIcp, 2.0), 1500 + 2 * 625);
	EXPECT_EQ(model.predict({Stage::kIcp}, 2.0), 2750);
	EXPECT_EQ(model.bound(Stage::kIcp, -1.0), 1500); // no negative margin
	for (int i = 0; i < 40; ++i)
		model.observe(Stage::kIcp, 1500); // steady: the spread dies away
	EXPECT_LE(model.bound(Stage::kIcp, 2.0), 1501); // (rounded up)
}

// One stall (a view search preempted for 50 ms in a run of 5 ms ones) must
// not price the stage out of the frames that follow: a stage that no longer
// runs is never observed again to correct the model. A lasting change still
// comes through.
TEST(StageCostModel, AStallDoesNotPriceAStageOutOfLaterFrames)
{
	StageCostModel model(0.3);
	for (int i = 0; i < 30; ++i)
		model.observe(Stage::kViews, i % 2 ? 5200 : 4800);
	const int64_t before = model.bound(Stage::kViews, 1.0);
	EXPECT_LT(before, 5500);
	model.observe(Stage::kViews, 52000);
	const int64_t after = model.bound(Stage::kViews, 1.0);
	RecordProperty("after_stall_ns", static_cast<int>(after));
	EXPECT_LT(after, 8000); // taken as is: 5000 + 0.3 * 47000, plus as much spread
	for (int i = 0; i < 3; ++i)
		model.observe(Stage::kViews, 5000);
	EXPECT_LT(model.bound(Stage::kViews, 1.0), 6500);
	// The machine slows down for good: twice the cost.
	for (int i = 0; i < 8; ++i)
		model.observe(Stage::kViews, 10000);
	EXPECT_GT(model.average(Stage::kViews), 9000);
	EXPECT_GE(model.bound(Stage::kViews, 1.0), 10000);
	// And speeds up again.
	for (int i = 0; i < 10; ++i)
		model.observe(Stage::kViews, 5000);
	EXPECT_LT(model.average(Stage::kViews), 5600);
}

// A stage refused by the budget is never observed again: each refusal
// eases its prediction, so that a cost measured too high once is tried
// again; the next observation measures it afresh.
TEST(StageCostModel, ARefusedStageEasesUntilItIsTriedAgain)
{
	StageCostModel model(0.3);
	model.observe(Stage::kViews, 8000); // a cold first run
	const int64_t room = 6000;           // what later boxes have left
	int refusals = 0;
	while (model.bound(Stage::kViews, 1.0) > room && refusals < 100) {
		model.refused(Stage::kViews);
		++refusals;
	}
	EXPECT_GT(refusals, 0);
	EXPECT_LE(refusals, 20); // 8000 x 1.25 = 10000 down to 6000: 17 at 0.97
	model.observe(Stage::kViews, 4000); // what it really costs
	EXPECT_LT(model.bound(Stage::kViews, 1.0), room);
	EXPECT_EQ(model.bound(Stage::kIcp, 1.0), 0); // other stages untouched
}

TEST(StageCostModel, ACostThatGrowsWithTheBoxIsPredictedPerUnitOfWork)
{
	StageCostModel model(0.5);
	model.observe(Stage::kIcp, 8000, 4000.0); // a large box: 2 ns per pixel
	EXPECT_EQ(model.average(Stage::kIcp), 2);
	EXPECT_EQ(model.bound(Stage::kIcp, 0.0, 500.0), 1000); // a small box's polish
	EXPECT_EQ(model.bound(Stage::kIcp, 2.0, 500.0), 1500); // spread: a quarter, scaled too
	model.observe(Stage::kIcp, 1500, 500.0);                // 3 ns per pixel
	EXPECT_EQ(model.bound(Stage::kIcp, 0.0, 1000.0), 2500);
	EXPECT_EQ(model.predict({Stage::kIcp}), 3); // predict() is per unit: rounded up
	model.observe(Stage::kViews, 6000); // a fixed cost, as before
	EXPECT_EQ(model.bound(Stage::kViews, 0.0), 6000);
}

TEST(FrameBudget, BoxesShareWhatIsLeft)
{
	FrameBudget b;
	b.beginFrame(0, 90, 3);
	b.beginBox(0);
	EXPECT_EQ(b.boxDeadline(), 30);
	EXPECT_TRUE(b.fits(10, 20));
	EXPECT_FALSE(b.fits(10, 21));
	b.endBox(20); // 10 unused go to the next boxes
	b.beginBox(20);
	EXPECT_EQ(b.boxDeadline(), 20 + 70 / 2);
	b.endBox(60); // past its share of 55
	b.beginBox(60);
	EXPECT_EQ(b.boxDeadline(), 90);
	b.endBox(95);
	b.endFrame(95);
	EXPECT_EQ(b.frames(), 1u);
	EXPECT_EQ(b.boxes(), 3u);
	EXPECT_EQ(b.boxOverruns(), 2u);
	EXPECT_EQ(b.frameOverruns(), 1u);
	EXPECT_EQ(b.worstFrameNs(), 95);
}

TEST(FrameBudget, ZeroMeansUnlimited)
{
	FrameBudget b;
	b.beginFrame(0, 0, 1);
	b.beginBox(0);
	EXPECT_TRUE(b.fits(1000000, 1000000000));
	b.endBox(5000000);
	b.endFrame(5000000);
	EXPECT_EQ(b.boxOverruns(), 0u);
	EXPECT_EQ(b.frameOverruns(), 0u);
}

TEST(FrameBudget, ALateBoxGetsNothingButIsStillCounted)
{
	FrameBudget b;
	b.beginFrame(0, 10, 2);
	b.beginBox(0);
	b.endBox(15);
	b.beginBox(15); // nothing left
	EXPECT_EQ(b.boxDeadline(), 15);
	EXPECT_TRUE(b.fits(15, 0));
	EXPECT_FALSE(b.fits(15, 1));
	b.endBox(16);
	b.endFrame(16);
	EXPECT_EQ(b.boxOverruns(), 2u);
	EXPECT_EQ(b.frameOverruns(), 1u);
}

} // namespace
} // namespace ihf
