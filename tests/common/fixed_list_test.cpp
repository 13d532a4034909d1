// SPDX-License-Identifier: MIT
#include "core/common/fixed_list.h"

#include <array>
#include <vector>

#include <gtest/gtest.h>

namespace ihf {
namespace {

struct Scored {
	float score = 0;
	int id = 0;
};

float scoreOf(const Scored &s)
{
	return s.score;
}

std::vector<int> ids(const FixedListBase<Scored> &list)
{
	std::vector<int> out;
	for (const Scored &s : list)
		out.push_back(s.id);
	return out;
}

// Taken by the base: one function serves every capacity.
size_t fill(FixedListBase<int> &list, int n)
{
	for (int i = 0; i < n; ++i)
		if (!list.pushBack(i))
			break;
	return list.size();
}

TEST(FixedList, StartsEmptyWithItsCapacity)
{
	FixedList<int, 4> list;
	EXPECT_TRUE(list.empty());
	EXPECT_FALSE(list.full());
	EXPECT_EQ(list.size(), 0u);
	EXPECT_EQ(list.capacity(), 4u);
	EXPECT_EQ(list.begin(), list.end());
}

TEST(FixedList, PushBackUpToCapacityThenReportsOverflow)
{
	FixedList<int, 3> list;
	EXPECT_TRUE(list.pushBack(1).ok());
	EXPECT_TRUE(list.pushBack(2).ok());
	EXPECT_TRUE(list.pushBack(3).ok());
	EXPECT_TRUE(list.full());
	const Status overflow = list.pushBack(4);
	ASSERT_FALSE(overflow.ok());
	EXPECT_EQ(overflow.error().code, Errc::kCapacity);
	EXPECT_TRUE(overflow.error().message.isLiteral()); // no heap on the error path
	EXPECT_EQ(list.size(), 3u);
	EXPECT_EQ(list.back(), 3);
}

TEST(FixedList, InsertAndEraseKeepOrder)
{
	FixedList<int, 4> list;
	ASSERT_TRUE(list.pushBack(1).ok());
	ASSERT_TRUE(list.pushBack(3).ok());
	ASSERT_TRUE(list.insert(1, 2).ok());
	ASSERT_TRUE(list.insert(0, 0).ok());
	EXPECT_EQ(std::vector<int>(list.begin(), list.end()), (std::vector<int>{0, 1, 2, 3}));
	EXPECT_EQ(list.insert(2, 9).error().code, Errc::kCapacity);
	list.erase(1);
	EXPECT_EQ(std::vector<int>(list.begin(), list.end()), (std::vector<int>{0, 2, 3}));
	list.truncate(1);
	EXPECT_EQ(std::vector<int>(list.begin(), list.end()), (std::vector<int>{0}));
	list.clear();
	EXPECT_TRUE(list.empty());
}

TEST(FixedList, BaseServesAnyCapacity)
{
	FixedList<int, 2> small;
	FixedList<int, 8> large;
	EXPECT_EQ(fill(small, 5), 2u);
	EXPECT_EQ(fill(large, 5), 5u);
}

TEST(FixedList, BaseOverExternalStorage)
{
	std::array<int, 3> storage{};
	FixedListBase<int> list(storage);
	EXPECT_EQ(list.capacity(), 3u);
	ASSERT_TRUE(list.pushBack(7).ok());
	EXPECT_EQ(storage[0], 7);
	std::array<int, 1> other{};
	list.setStorage(other);
	EXPECT_TRUE(list.empty());
	EXPECT_EQ(list.capacity(), 1u);
}

TEST(FixedList, CopiesItsElementsNotItsStorage)
{
	FixedList<int, 3> a;
	ASSERT_TRUE(a.pushBack(1).ok());
	ASSERT_TRUE(a.pushBack(2).ok());
	FixedList<int, 3> b = a;
	a[0] = 5;
	EXPECT_EQ(b.size(), 2u);
	EXPECT_EQ(b[0], 1);
	EXPECT_NE(b.begin(), a.begin());
	b = a;
	EXPECT_EQ(b[0], 5);
}

TEST(InsertRanked, KeepsBestFirstAndEqualsInArrivalOrder)
{
	FixedList<Scored, 4> list;
	EXPECT_TRUE(insertRanked(list, Scored{0.5f, 1}, scoreOf));
	EXPECT_TRUE(insertRanked(list, Scored{0.9f, 2}, scoreOf));
	EXPECT_TRUE(insertRanked(list, Scored{0.5f, 3}, scoreOf)); // after the equal one
	EXPECT_TRUE(insertRanked(list, Scored{0.1f, 4}, scoreOf));
	EXPECT_EQ(ids(list), (std::vector<int>{2, 1, 3, 4}));
}

TEST(InsertRanked, FullListDropsItsWorstOrTheNewcomer)
{
	FixedList<Scored, 3> list;
	insertRanked(list, Scored{0.3f, 1}, scoreOf);
	insertRanked(list, Scored{0.2f, 2}, scoreOf);
	insertRanked(list, Scored{0.1f, 3}, scoreOf);
	// Not better than the worst: left out.
	EXPECT_FALSE(insertRanked(list, Scored{0.1f, 4}, scoreOf));
	EXPECT_EQ(ids(list), (std::vector<int>{1, 2, 3}));
	// Better: the worst goes.
	EXPECT_TRUE(insertRanked(list, Scored{0.25f, 5}, scoreOf));
	EXPECT_EQ(ids(list), (std::vector<int>{1, 5, 2}));
	EXPECT_TRUE(insertRanked(list, Scored{0.9f, 6}, scoreOf));
	EXPECT_EQ(ids(list), (std::vector<int>{6, 1, 5}));
}

TEST(InsertRanked, ZeroCapacityTakesNothing)
{
	FixedListBase<Scored> list;
	EXPECT_FALSE(insertRanked(list, Scored{1.0f, 1}, scoreOf));
	EXPECT_TRUE(list.empty());
}

} // namespace
} // namespace ihf
