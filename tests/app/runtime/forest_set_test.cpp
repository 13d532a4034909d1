// SPDX-License-Identifier: MIT
// The one forest-loading path of ihf estimate and ihf run
// (firmware_app/runtime/forest_set.h): OBJ_ID=FILE options parsed with clear
// errors, each forest loaded and prepared, the estimator's limits grown to
// hold it, and a missing or bad file refused naming the file.

#include <fstream>

#include <gtest/gtest.h>

#include "firmware_app/runtime/forest_set.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

TEST(ForestSet, OptionsAreObjectIdEqualsFile)
{
	auto parsed = parseForestOptions({"5=a.ihf", "12=/b/c.ihf"});
	ASSERT_TRUE(parsed) << parsed.error().message;
	ASSERT_EQ(parsed->size(), 2u);
	EXPECT_EQ(parsed->at(5), "a.ihf");
	EXPECT_EQ(parsed->at(12), "/b/c.ihf");
}

TEST(ForestSet, AMalformedOrRepeatedOptionIsNamed)
{
	for (const char *bad : {"a.ihf", "x=a.ihf", "-1=a.ihf", "5="}) {
		auto parsed = parseForestOptions({bad});
		ASSERT_FALSE(parsed) << bad;
		EXPECT_NE(parsed.error().message.find(bad), std::string::npos) << parsed.error().message;
	}
	auto twice = parseForestOptions({"5=a.ihf", "5=b.ihf"});
	ASSERT_FALSE(twice);
	EXPECT_NE(twice.error().message.find("object 5 twice"), std::string::npos) << twice.error().message;
}

TEST(ForestSet, LoadsPreparesAndSizesTheLimits)
{
	EstimateSettings settings;
	settings.limits.maxHistogramDims = 1;
	settings.limits.maxMeshVertices = 1;
	auto set = ForestSet::load({{7, test::goldenForest()}}, settings, "test");
	ASSERT_TRUE(set) << set.error().message;
	ASSERT_NE(set->find(7), nullptr);
	EXPECT_EQ(set->find(8), nullptr);
	EXPECT_EQ(set->models().size(), 1u);
	const ObjectModel &m = *set->find(7);
	EXPECT_GE(settings.limits.maxHistogramDims, m.forest().dims);
	EXPECT_GE(settings.limits.maxMeshVertices, m.renderMesh().vertices.size());
}

TEST(ForestSet, AMissingOrBadFileIsRefusedByName)
{
	EstimateSettings settings;
	const std::filesystem::path missing = std::filesystem::temp_directory_path() / "ihf_no_such_forest.ihf";
	auto set = ForestSet::load({{1, missing}}, settings, "test");
	ASSERT_FALSE(set);
	EXPECT_NE(set.error().message.find("ihf_no_such_forest.ihf"), std::string::npos) << set.error().message;

	const std::filesystem::path bad = std::filesystem::temp_directory_path() / "ihf_bad_forest.ihf";
	std::ofstream(bad) << "not a forest";
	set = ForestSet::load({{1, test::goldenForest()}, {2, bad}}, settings, "test");
	ASSERT_FALSE(set);
	EXPECT_NE(set.error().message.find("ihf_bad_forest.ihf"), std::string::npos) << set.error().message;
	std::filesystem::remove(bad);
}

} // namespace
} // namespace ihf::app
