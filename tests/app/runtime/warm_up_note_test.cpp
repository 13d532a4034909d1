// SPDX-License-Identifier: MIT
#include <string>

#include <gtest/gtest.h>

#include "firmware_app/runtime/warm_up_note.h"

namespace ihf::app {
namespace {

bool has(const std::string &s, const char *part)
{
	return s.find(part) != std::string::npos;
}

// A frame shorter than the warm-up's initial registration is said, with the
// object, both times and why it overruns; a frame it fits, or no budget, is
// not.
TEST(WarmUpNote, AFrameShorterThanTheRegistrationIsSaid)
{
	const WarmUpCost cost{12.34, 30.0};
	const std::string note = warmUpNote(20, cost, 10.0f);
	EXPECT_TRUE(has(note, "object 20")) << note;
	EXPECT_TRUE(has(note, "12.3 ms")) << note;
	EXPECT_TRUE(has(note, "10 ms frame budget")) << note;
	EXPECT_TRUE(has(note, "overrun")) << note;
	EXPECT_EQ(warmUpNote(20, cost, 12.5f), "") << "the registration fits; the rest is cut to the frame";
	EXPECT_EQ(warmUpNote(20, cost, 0.0f), "") << "no budget";
	EXPECT_FALSE(has(note, "tight")) << note;
	WarmUpCost tight = cost;
	tight.tight = true;
	EXPECT_TRUE(has(warmUpNote(20, tight, 10.0f), "12.3 ms on the largest box (the tight profile)"));
}

TEST(WarmUpNote, AFailedWarmUpSaysWhyAndWhatFollows)
{
	const Expected<WarmUpCost> failed = makeError(Errc::kNoPose, "warm-up box gave no pose: too few points");
	const std::string note = warmUpNote(5, failed, 33.0f);
	EXPECT_TRUE(has(note, "object 5")) << note;
	EXPECT_TRUE(has(note, "too few points")) << note;
	EXPECT_TRUE(has(note, "first box may overrun")) << note;
}

} // namespace
} // namespace ihf::app
