// SPDX-License-Identifier: MIT
// The leads on the pixels where a pose and its rival differ: a rival the
// depth favours two to one replaces the best; the best is certain only on
// three to one; a lead of fewer than minPixels does neither.

#include <gtest/gtest.h>

#include "core/estimation/symmetry_turn_config.h"

namespace ihf {
namespace {

TEST(SymmetryTurnConfig, ATwoToOneLeadReplacesTheBestButDoesNotMakeItCertain)
{
	const SymmetryTurnConfig c;
	// A bottle upside down against its upright turn, the nozzle seen:
	// 609 pixels for the turn, 277 for the best.
	EXPECT_TRUE(preferredBy(609, 277, 609 + 277, c));
	EXPECT_FALSE(decisivelyBy(609, 277, 609 + 277, c));
	// Three to one is both.
	EXPECT_TRUE(decisivelyBy(300, 100, 400, c));
	EXPECT_TRUE(preferredBy(300, 100, 400, c));
	// Fewer than minPixels ahead is neither, however lopsided.
	EXPECT_FALSE(preferredBy(c.minPixels - 1, 0, c.minPixels - 1, c));
	// Even is neither.
	EXPECT_FALSE(preferredBy(200, 200, 400, c));
}

} // namespace
} // namespace ihf
