// SPDX-License-Identifier: MIT
// readRunPoses(): the pose and error lines of `ihf run`, and each kind of
// malformed line failing with the file and line named.

#include <fstream>

#include <gtest/gtest.h>

#include "core/eval/run_poses.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

fs::path writeLines(const fs::path &dir, const std::string &text)
{
	const fs::path file = dir / "poses.jsonl";
	std::ofstream(file, std::ios::binary) << text;
	return file;
}

// Two good lines, as `ihf run` writes them.
const std::string kGoodLines =
	R"({"frame":0,"obj_id":20,"R":[0,-1,0,1,0,0,0,0,1],"t":[-12.5,30.25,845],"confidence":0.7,)"
	R"("score":0.8,"margin":0.9,"iterations":5,"best_iteration":3,"icp":true,"latency_ms":61.2,)"
	R"("estimate_ms":58.9,"mode":"detect","track_id":1})"
	"\n"
	R"({"frame":1,"obj_id":20,"mode":"track","track_id":1,"error":"deferred"})"
	"\n";

TEST(RunPoses, ReadsPoseAndErrorLines)
{
	const fs::path dir = test::freshTempDir("run_poses_read");
	const fs::path file = writeLines(dir, kGoodLines + "\r\n   \n" + R"({"error":"source ended"})" + "\r\n" +
						      R"({"obj_id":3,"error":""})" + "\n");
	auto lines = readRunPoses(file);
	ASSERT_TRUE(lines.ok()) << lines.error().message;
	ASSERT_EQ(lines->size(), 4u);

	const RunPoseLine &pose = (*lines)[0];
	EXPECT_EQ(pose.line, 1u);
	EXPECT_EQ(pose.frame, 0u);
	EXPECT_EQ(pose.objId, 20);
	ASSERT_TRUE(pose.pose.has_value());
	EXPECT_EQ(pose.pose->R(0, 1), -1.0); // row-major
	EXPECT_EQ(pose.pose->R(1, 0), 1.0);
	EXPECT_EQ(pose.pose->R(2, 2), 1.0);
	EXPECT_EQ(pose.pose->t, Eigen::Vector3d(-12.5, 30.25, 845));

	const RunPoseLine &deferred = (*lines)[1];
	EXPECT_EQ(deferred.line, 2u);
	EXPECT_FALSE(deferred.pose.has_value());
	EXPECT_EQ(deferred.frame, 1u);
	EXPECT_EQ(deferred.objId, 20);
	EXPECT_EQ(deferred.error, "deferred");

	EXPECT_EQ((*lines)[2].line, 5u); // blank lines counted, not read
	EXPECT_FALSE((*lines)[2].frame.has_value());
	EXPECT_FALSE((*lines)[2].objId.has_value());
	EXPECT_EQ((*lines)[2].error, "source ended");
	EXPECT_EQ((*lines)[3].objId, 3);
	EXPECT_EQ((*lines)[3].error, "");

	auto empty = readRunPoses(writeLines(dir, ""));
	ASSERT_TRUE(empty.ok());
	EXPECT_TRUE(empty->empty());
}

TEST(RunPoses, EachMalformedLineNamesTheFileAndLine)
{
	const fs::path dir = test::freshTempDir("run_poses_bad");
	const std::string pose = R"("frame":2,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900])";
	const struct {
		std::string line;
		std::string why;
	} cases[] = {
		{"not json", "not JSON"},
		{R"({"frame":2,)", "not JSON"},
		{"[1,2,3]", "not a JSON object"},
		{R"({"obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "no \"frame\""},
		{R"({"frame":2,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "no \"obj_id\""},
		{R"({"frame":2,"obj_id":20,"t":[0,0,900]})", "no \"R\""},
		{R"({"frame":2,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1]})", "no \"t\""},
		{R"({"frame":-1,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "\"frame\" is not a non-negative integer"},
		{R"({"frame":"2","obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "\"frame\" is not"},
		{R"({"frame":2.5,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "\"frame\" is not"},
		{R"({"frame":2,"obj_id":0,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "\"obj_id\" is not a positive integer"},
		{R"({"frame":2,"obj_id":4294967296,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0,900]})", "\"obj_id\" is not"},
		{R"({"frame":2,"obj_id":20,"R":[1,0,0,0,1,0,0,0],"t":[0,0,900]})", "\"R\" is not 9 numbers"},
		{R"({"frame":2,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1,0],"t":[0,0,900]})", "\"R\" is not 9 numbers"},
		{R"({"frame":2,"obj_id":20,"R":[1,0,0,0,"1",0,0,0,1],"t":[0,0,900]})", "\"R\" is not 9 numbers"},
		{R"({"frame":2,"obj_id":20,"R":"identity","t":[0,0,900]})", "\"R\" is not 9 numbers"},
		{R"({"frame":2,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,0]})", "\"t\" is not 3 numbers"},
		{R"({"frame":2,"obj_id":20,"R":[1,0,0,0,1,0,0,0,1],"t":[0,null,900]})", "\"t\" is not 3 numbers"},
		{R"({"frame":2,"error":17})", "\"error\" is not a string"},
		{R"({"frame":-2,"error":"x"})", "\"frame\" is not"},
		{R"({"obj_id":-3,"error":"x"})", "\"obj_id\" is not"},
	};
	for (const auto &c : cases) {
		const fs::path file = writeLines(dir, kGoodLines + c.line + "\n{" + pose + "}\n");
		auto lines = readRunPoses(file);
		ASSERT_FALSE(lines.ok()) << c.line;
		EXPECT_EQ(lines.error().code, Errc::kParse) << c.line;
		const std::string &message = lines.error().message;
		EXPECT_EQ(message.rfind(file.string() + " line 3: ", 0), 0u) << c.line << " -> " << message;
		EXPECT_NE(message.find(c.why), std::string::npos) << c.line << " -> " << message;
	}
}

TEST(RunPoses, AMissingFileIsNamed)
{
	const fs::path file = test::freshTempDir("run_poses_missing") / "absent.jsonl";
	auto lines = readRunPoses(file);
	ASSERT_FALSE(lines.ok());
	EXPECT_EQ(lines.error().code, Errc::kIo);
	EXPECT_NE(lines.error().message.find("absent.jsonl"), std::string::npos) << lines.error().message;
}

} // namespace
} // namespace ihf
