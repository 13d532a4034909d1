// SPDX-License-Identifier: MIT
// ModelParams <-> JSON: exact round trip, enums as strings, strict reading
// with errors that name the field.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/model/model_params_json.h"
#include "tests/model/model_fixture.h"

namespace ihf {
namespace {

using nlohmann::json;

json toJsonDoc(const ModelParams &p)
{
	auto text = modelParamsToJson(p);
	EXPECT_TRUE(text.ok());
	return json::parse(*text);
}

Error parseError(const json &doc)
{
	auto r = modelParamsFromJson(doc.dump(), "obj.ihf: PARAMS");
	EXPECT_FALSE(r.ok());
	return r.ok() ? Error{} : r.error();
}

TEST(ModelParamsJson, RoundTripIsExact)
{
	const ModelParams p = test::makeParams();
	auto text = modelParamsToJson(p);
	ASSERT_TRUE(text.ok()) << text.error().message;
	auto back = modelParamsFromJson(*text, "test");
	ASSERT_TRUE(back.ok()) << back.error().message;
	test::expectParamsEqual(p, *back);

	// Defaults too.
	auto defText = modelParamsToJson(ModelParams{});
	ASSERT_TRUE(defText.ok());
	auto def = modelParamsFromJson(*defText, "test");
	ASSERT_TRUE(def.ok()) << def.error().message;
	test::expectParamsEqual(ModelParams{}, *def);
}

TEST(ModelParamsJson, EnumsAreStringsAndFloatsShort)
{
	const json doc = toJsonDoc(test::makeParams());
	EXPECT_EQ(doc["hocp"]["weighting"], "sign_split");
	EXPECT_EQ(doc["parts"]["kind"], "fixed");
	EXPECT_EQ(doc["parts"]["cap"], "largest_weight");
	EXPECT_EQ(doc["ibs"]["solver"], "multilevel_ba");
	EXPECT_EQ(doc["ibs"]["warm_start"], "previous");
	EXPECT_EQ(doc["training"]["seed"].get<uint64_t>(), 18446744073709551557ull);
	// 0.07f is printed as 0.07, not as its widened double 0.07000000029802322.
	auto text = modelParamsToJson(test::makeParams());
	EXPECT_NE(text->find("\"r_min_fraction\": 0.07,"), std::string::npos) << *text;
}

TEST(ModelParamsJson, MissingFieldIsNamed)
{
	json doc = toJsonDoc(test::makeParams());
	doc["hocp"].erase("n_phi");
	Error e = parseError(doc);
	EXPECT_EQ(e.code, Errc::kParse);
	EXPECT_NE(e.message.find("obj.ihf: PARAMS: hocp.n_phi: missing field"), std::string::npos)
		<< e.message;
}

TEST(ModelParamsJson, WrongTypeIsNamed)
{
	json doc = toJsonDoc(test::makeParams());
	doc["ibs"]["n"] = "fifty";
	Error e = parseError(doc);
	EXPECT_NE(e.message.find("ibs.n: expected an integer, got string"), std::string::npos)
		<< e.message;

	doc = toJsonDoc(test::makeParams());
	doc["cloud"]["max_jump_mm"] = true;
	e = parseError(doc);
	EXPECT_NE(e.message.find("cloud.max_jump_mm: expected a number"), std::string::npos)
		<< e.message;

	doc = toJsonDoc(test::makeParams());
	doc["training"]["scales"][1] = "x";
	e = parseError(doc);
	EXPECT_NE(e.message.find("training.scales[1]: expected a number"), std::string::npos)
		<< e.message;

	doc = toJsonDoc(test::makeParams());
	doc["parts"] = 3;
	e = parseError(doc);
	EXPECT_NE(e.message.find("parts: expected an object"), std::string::npos) << e.message;
}

TEST(ModelParamsJson, BadEnumListsTheChoices)
{
	json doc = toJsonDoc(test::makeParams());
	doc["hocp"]["weighting"] = "squared";
	Error e = parseError(doc);
	EXPECT_NE(e.message.find("hocp.weighting: unknown value \"squared\" (expected one of count, "
				 "abs_weight, sign_split)"),
		  std::string::npos)
		<< e.message;
}

TEST(ModelParamsJson, UnknownFieldRejected)
{
	json doc = toJsonDoc(test::makeParams());
	doc["hocp"]["n_psi"] = 3;
	Error e = parseError(doc);
	EXPECT_NE(e.message.find("hocp.n_psi: unknown field"), std::string::npos) << e.message;

	doc = toJsonDoc(test::makeParams());
	doc["colour"] = "red";
	e = parseError(doc);
	EXPECT_NE(e.message.find("colour: unknown field"), std::string::npos) << e.message;
}

TEST(ModelParamsJson, OutOfRangeValues)
{
	json doc = toJsonDoc(test::makeParams());
	doc["hocp"]["n_r"] = 0;
	Error e = parseError(doc);
	EXPECT_EQ(e.code, Errc::kOutOfRange);
	EXPECT_NE(e.message.find("hocp.n_r: must be at least 1, got 0"), std::string::npos)
		<< e.message;

	doc = toJsonDoc(test::makeParams());
	doc["obj_id"] = 1ll << 40;
	e = parseError(doc);
	EXPECT_NE(e.message.find("obj_id: integer out of range"), std::string::npos) << e.message;

	doc = toJsonDoc(test::makeParams());
	doc["training"]["seed"] = -1;
	e = parseError(doc);
	EXPECT_NE(e.message.find("training.seed: expected a non-negative integer"), std::string::npos)
		<< e.message;
}

TEST(ModelParamsJson, MalformedTextNamesTheSource)
{
	auto r = modelParamsFromJson("{\"obj_id\": 3,", "model.ihf: PARAMS");
	ASSERT_FALSE(r.ok());
	EXPECT_EQ(r.error().code, Errc::kParse);
	EXPECT_NE(r.error().message.find("model.ihf: PARAMS: malformed JSON"), std::string::npos)
		<< r.error().message;
}

TEST(ModelParamsJson, NonFiniteCannotBeWritten)
{
	ModelParams p = test::makeParams();
	p.ibs.ridge = std::numeric_limits<float>::quiet_NaN();
	auto r = modelParamsToJson(p);
	ASSERT_FALSE(r.ok());
	EXPECT_NE(r.error().message.find("ibs.ridge: not a finite number"), std::string::npos)
		<< r.error().message;

	p = test::makeParams();
	p.trainScales[2] = std::numeric_limits<float>::infinity();
	r = modelParamsToJson(p);
	ASSERT_FALSE(r.ok());
	EXPECT_NE(r.error().message.find("training.scales[2]"), std::string::npos)
		<< r.error().message;
}

} // namespace
} // namespace ihf
