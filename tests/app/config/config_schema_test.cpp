// SPDX-License-Identifier: MIT
// The key descriptors (firmware_app/config/config_keys.cpp) drive the readers, the
// range checks, `ihf config` and docs/configuration.md: every default lies
// in its key's range; the shipped files hold the user settings, at their
// defaults; profiles override only what they list; unknown keys and values
// out of range name the file, table and key; the reference in docs/ is the
// generator's.

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "firmware_app/config/config_reference.h"
#include "firmware_app/config/config_schema.h"
#include "firmware_app/config/pipeline_config.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

namespace fs = std::filesystem;

fs::path writeFile(const std::string &dir, const std::string &text)
{
	const fs::path d = test::freshTempDir("config_schema_" + dir);
	std::ofstream(d / "c.toml") << text;
	return d / "c.toml";
}

TEST(ConfigSchema, EveryKeyIsDeclaredOnceWithItsMeaningAndItsDefaultInRange)
{
	for (const Schema *schema : schemas()) {
		std::set<std::string> seen;
		for (const KeyDesc &k : schema->keys) {
			EXPECT_TRUE(seen.insert(k.path()).second) << schema->kind << ": " << k.path() << " twice";
			EXPECT_GT(std::string(k.meaning).size(), 0u) << k.path();
		}
		SettingsOf defaults(*schema);
		const Status st = checkRanges(schema->kind, *schema, defaults.get());
		EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message.c_str());
	}
}

// Each shipped file holds exactly the keys a user tunes (and the
// installation's own), every one at the code's default but the
// installation's.
TEST(ConfigSchema, TheShippedFilesHoldTheUserSettingsAtTheirDefaults)
{
	for (const Schema *schema : schemas()) {
		const fs::path file = test::sourceDir() / schema->file;
		auto held = keysInFile(file);
		ASSERT_TRUE(held.ok()) << held.error().message;
		std::set<std::string> inFile;
		for (const std::string &k : *held) {
			bool free = false;
			for (const char *t : schema->freeTables)
				free = free || k.starts_with(std::string(t) + ".");
			if (!free)
				inFile.insert(k);
		}
		std::set<std::string> users;
		for (const KeyDesc &k : schema->keys)
			if (k.audience != Audience::kExpert)
				users.insert(k.path());
		EXPECT_EQ(inFile, users) << schema->file << " holds other keys than the user settings";
		if (std::string(schema->kind) == "estimate") {
			EXPECT_LE(inFile.size(), 25u);
		}

		SettingsOf loaded(*schema), defaults(*schema);
		const Status st = schema->load(file, loaded.get());
		ASSERT_TRUE(st.ok()) << st.error().message;
		for (const KeyDesc &k : schema->keys) {
			if (k.audience != Audience::kSite && inFile.count(k.path())) {
				EXPECT_EQ(showValue(k, loaded.get()), showValue(k, defaults.get()))
					<< schema->file << ": " << k.path() << " differs from the code's default";
			}
		}
	}
}

// A profile table lists only what it changes: the rest of the profile keeps
// its defaults, and the base settings are untouched.
TEST(ConfigSchema, ProfilesAreSparseOverrides)
{
	auto s = loadEstimateConfig(writeFile("profiles", "[budget.view_search]\nrefine_top = 10\n"
							   "[tight.votes]\nmax_hypotheses = 1\n"
							   "[short.score]\noccluded_weight = 0.3\n"
							   "[iteration.refinement]\ntarget_parts = 50\n"
							   "[modal_boxes.score]\nbox_weight = 2.0\n"));
	ASSERT_TRUE(s.ok()) << s.error().message;
	const EstimatorConfig &e = s->estimator;
	SettingsOf defaults(estimateSchema());
	const Schema &schema = estimateSchema();
	const std::set<std::string> changed = {"budget.view_search.refine_top", "tight.votes.max_hypotheses",
					       "short.score.occluded_weight", "iteration.refinement.target_parts",
					       "modal_boxes.score.box_weight"};
	for (const KeyDesc &k : schema.keys) {
		if (!changed.count(k.path())) {
			EXPECT_EQ(showValue(k, &*s), showValue(k, defaults.get())) << k.path();
		}
	}
	EXPECT_EQ(e.views.budgetRefineTop, 10);
	EXPECT_EQ(s->modal.boxWeight, 2.0f);

	// What each profile runs with.
	const EstimatorConfig base = e;
	EXPECT_EQ(underBudget(base).views.refineTop, 10);
	EXPECT_EQ(underBudget(base).maxHypotheses, base.maxHypotheses);
	const ShareSettings tight = underShare(base, 10.0); // under both thresholds
	ASSERT_TRUE(tight.tight && tight.shortRounds);
	EXPECT_EQ(tight.config.maxHypotheses, 1);
	EXPECT_EQ(tight.config.score.occludedWeight, 0.3f);
	const ShareSettings roomy = underShare(base, 30.0);
	EXPECT_FALSE(roomy.tight || roomy.shortRounds);
	EXPECT_EQ(roomy.config.maxHypotheses, base.maxHypotheses);
	EXPECT_EQ(roomy.config.score.occludedWeight, base.score.occludedWeight);
	EXPECT_EQ(forIterations(base).targetParts, 50);
	EXPECT_EQ(base.targetParts, EstimatorConfig{}.targetParts);
}

TEST(ConfigSchema, UnknownKeysTablesAndRangesNameTheFileTableAndKey)
{
	struct Case {
		const char *text, *expect;
	};
	for (const Case &c : {Case{"[budget.view_search]\nrefine_topp = 3\n", "unknown key budget.view_search.refine_topp"},
			      Case{"[budget.search]\nx = 1\n", "unknown section [budget.search]"},
			      Case{"[tight]\nbelow = 3\n", "unknown key tight.below"},
			      Case{"[view_search]\nkeep = 0\n", "view_search.keep: out of range: 0 (allowed: [1, 16])"},
			      Case{"[budget.refinement]\ntarget_parts = 0\n", "budget.refinement.target_parts: out of range"},
			      Case{"[refinement]\niterations = 2.5\n", "refinement.iterations: expected an integer"},
			      Case{"[boxes]\nkind = \"visible\"\n", "boxes.kind: unknown value \"visible\""}}) {
		auto s = loadEstimateConfig(writeFile("errors", c.text));
		ASSERT_FALSE(s.ok()) << c.text;
		EXPECT_NE(s.error().message.find(c.expect), std::string::npos) << s.error().message;
		EXPECT_NE(s.error().message.find("c.toml"), std::string::npos) << s.error().message;
	}
}

TEST(ConfigSchema, TheEffectiveConfigShowsValuesDefaultsAndMeanings)
{
	auto s = loadEstimateConfig(writeFile("effective", "[refinement]\niterations = 3\n[budget]\n"
							     "estimation_budget_ms = 20.5\n"));
	ASSERT_TRUE(s.ok()) << s.error().message;
	const std::string text = effectiveConfig(estimateSchema(), &*s, "c.toml");
	EXPECT_NE(text.find("[refinement]\niterations = 3"), std::string::npos) << text;
	EXPECT_NE(text.find("# default 5; k: refinement iterations"), std::string::npos) << text;
	EXPECT_NE(text.find("estimation_budget_ms = 20.5"), std::string::npos) << text;
	EXPECT_NE(text.find("[budget.view_search]"), std::string::npos) << text;
	// A key at its default shows no default.
	EXPECT_NE(text.find("inlier_mm = 10.0"), std::string::npos) << text;

	const test::CommandResult r = test::runIhf("config --only device");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("drop_frames_older_than_ms = 0.0"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("# estimation_budget_ms unset"), std::string::npos) << r.output;
	EXPECT_EQ(r.output.find("[refinement]"), std::string::npos) << "--only device printed the estimate config";
}

// docs/configuration.md is generated; a change to a key must regenerate it.
TEST(ConfigSchema, TheConfigurationReferenceIsCurrent)
{
	const fs::path doc = test::sourceDir() / "docs" / "configuration.md";
	std::ifstream in(doc);
	std::stringstream text;
	text << in.rdbuf();
	EXPECT_TRUE(text.str() == configurationMarkdown())
		<< "docs/configuration.md is stale; regenerate it: build/bin/ihf config --markdown > docs/configuration.md";
}

} // namespace
} // namespace ihf::app
