// SPDX-License-Identifier: MIT
// Box lines in, pose and error lines out: frame matching (skipped, pending,
// end), malformed lines and boxes reported while the good boxes go on, the
// unix socket both ways, and the pose line's exact numbers.

#include <charconv>
#include <fstream>
#include <thread>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "firmware_app/runtime/box_feed.h"
#include "firmware_app/runtime/pose_output.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

void writeText(const fs::path &file, const std::string &text)
{
	std::ofstream(file, std::ios::binary) << text;
}

TEST(BoxFeed, MatchesLinesToFrames)
{
	const fs::path dir = test::freshTempDir("box_feed_match");
	writeText(dir / "b.jsonl",
		  "{\"frame\": 1, \"boxes\": [{\"obj_id\": 5, \"bbox\": [10, 20, 30, 40]}]}\n"
		  "{\"frame\": 2, \"boxes\": [{\"obj_id\": 6, \"bbox\": [1.5, 2.5, 3.5, 4.5]}]}\n"
		  "{\"frame\": 4, \"boxes\": [{\"obj_id\": 7, \"bbox\": [0, 0, 8, 8]}, {\"obj_id\": 8, \"bbox\": [1, 1, 2, 2]}]}\n"
		  "{\"frame\": 7, \"boxes\": []}"); // no final newline
	auto feed = BoxFeed::open("file:" + (dir / "b.jsonl").string());
	ASSERT_TRUE(feed.ok()) << feed.error().message;
	BoxFeed &f = **feed;
	EXPECT_FALSE(f.live());

	EXPECT_EQ(*f.wait(0, milliseconds(0)), BoxWait::kNone); // line 1 is for later
	ASSERT_EQ(*f.wait(1, milliseconds(0)), BoxWait::kBoxes);
	ASSERT_EQ(f.boxes().size(), 1u);
	EXPECT_EQ(f.boxes()[0].objId, 5);
	EXPECT_EQ(f.boxes()[0].bbox, (std::array<double, 4>{10, 20, 30, 40}));
	EXPECT_EQ(*f.wait(3, milliseconds(0)), BoxWait::kNone); // frame 2's line skipped
	EXPECT_EQ(f.counters().skipped, 1u);
	ASSERT_EQ(*f.wait(4, milliseconds(0)), BoxWait::kBoxes);
	ASSERT_EQ(f.boxes().size(), 2u);
	EXPECT_EQ(f.boxes()[1].objId, 8);
	ASSERT_EQ(*f.wait(7, milliseconds(0)), BoxWait::kBoxes);
	EXPECT_TRUE(f.boxes().empty());
	EXPECT_EQ(*f.wait(8, milliseconds(0)), BoxWait::kEnd);
	EXPECT_EQ(f.counters().lines, 4u);
}

TEST(BoxFeed, MalformedLinesAndBoxesAreReportedTheRestGoesOn)
{
	const fs::path dir = test::freshTempDir("box_feed_bad");
	writeText(dir / "b.jsonl",
		  "not json\n"
		  "{\"frame\": -1, \"boxes\": []}\n"
		  "\n"
		  "{\"frame\": 3, \"boxes\": [{\"obj_id\": 1, \"bbox\": [0, 0, 0, 5]}, "
		  "{\"obj_id\": 2, \"bbox\": [1, 2, 3, 4]}, {\"obj_id\": \"x\", \"bbox\": [1, 2, 3, 4]}, "
		  "{\"obj_id\": 4, \"bbox\": [1, 2, 3]}, {\"obj_id\": 5, \"bbox\": [1e300, 2, 3, 4]}]}\n");
	auto feed = BoxFeed::open("file:" + (dir / "b.jsonl").string());
	ASSERT_TRUE(feed.ok());
	BoxFeed &f = **feed;
	ASSERT_EQ(*f.wait(3, milliseconds(0)), BoxWait::kBoxes);
	ASSERT_EQ(f.boxes().size(), 1u);
	EXPECT_EQ(f.boxes()[0].objId, 2);
	ASSERT_EQ(f.problems().size(), 6u);
	EXPECT_NE(f.problems()[0].find("b.jsonl line 1: not a JSON object"), std::string::npos) << f.problems()[0];
	EXPECT_NE(f.problems()[1].find("line 2: \"frame\""), std::string::npos) << f.problems()[1];
	EXPECT_NE(f.problems()[2].find("line 4: box 0: \"bbox\""), std::string::npos) << f.problems()[2];
	EXPECT_NE(f.problems()[3].find("line 4: box 2: \"obj_id\""), std::string::npos) << f.problems()[3];
	EXPECT_NE(f.problems()[4].find("line 4: box 3: \"bbox\""), std::string::npos) << f.problems()[4];
	// A coordinate no int pixel box can hold.
	EXPECT_NE(f.problems()[5].find("line 4: box 4: \"bbox\" must be [x, y, w, h] with w, h > 0, each within +-1e6"),
		  std::string::npos)
		<< f.problems()[5];
	EXPECT_EQ(f.counters().malformed, 6u);
}

TEST(BoxFeed, BadSpecsAreRefused)
{
	EXPECT_FALSE(BoxFeed::open("tcp:1234").ok());
	auto missing = BoxFeed::open("file:/nonexistent/boxes.jsonl");
	ASSERT_FALSE(missing.ok());
	EXPECT_NE(missing.error().message.find("/nonexistent/boxes.jsonl"), std::string::npos);
	const fs::path dir = test::freshTempDir("box_feed_spec");
	writeText(dir / "plain", "x");
	auto notSocket = BoxFeed::open("unix:" + (dir / "plain").string());
	ASSERT_FALSE(notSocket.ok());
	EXPECT_NE(notSocket.error().message.find("not a socket"), std::string::npos);
	EXPECT_FALSE(PoseOutput::open("socket", nullptr).ok());
	EXPECT_FALSE(PoseOutput::open("udp:1", nullptr).ok());
}

TEST(BoxFeed, UnixSocketBothWays)
{
	const fs::path dir = test::freshTempDir("box_feed_unix");
	const std::string path = (dir / "ihf.sock").string();
	auto feed = BoxFeed::open("unix:" + path);
	ASSERT_TRUE(feed.ok()) << feed.error().message;
	auto out = PoseOutput::open("socket", feed->get());
	ASSERT_TRUE(out.ok()) << out.error().message;

	std::string received;
	std::thread detector([&] {
		int s = socket(AF_UNIX, SOCK_STREAM, 0);
		sockaddr_un a{};
		a.sun_family = AF_UNIX;
		std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
		ASSERT_EQ(connect(s, reinterpret_cast<sockaddr *>(&a), sizeof(a)), 0);
		const std::string lines = "{\"frame\": 5, \"boxes\": [{\"obj_id\": 3, \"bbox\": [4, 5, 6, 7]}]}\n";
		ASSERT_EQ(write(s, lines.data(), lines.size()), static_cast<ssize_t>(lines.size()));
		char buf[512];
		ssize_t n;
		while ((n = read(s, buf, sizeof(buf))) > 0) {
			received.append(buf, n);
			if (received.find('\n') != std::string::npos)
				break;
		}
		close(s);
	});
	ASSERT_EQ(*(*feed)->wait(5, milliseconds(5000)), BoxWait::kBoxes);
	ASSERT_EQ((*feed)->boxes().size(), 1u);
	EXPECT_EQ((*feed)->boxes()[0].objId, 3);
	ASSERT_TRUE((*out)->writeError(5, 3, "no forest for object 3").ok());
	detector.join();
	EXPECT_EQ(received, "{\"frame\":5,\"obj_id\":3,\"error\":\"no forest for object 3\"}\n");
	EXPECT_EQ((*feed)->counters().clients, 1u);
	// A live input with nothing coming times out.
	EXPECT_EQ(*(*feed)->wait(6, milliseconds(50)), BoxWait::kNone);
}

TEST(PoseOutput, PoseLinesCarryExactNumbersAndFilesAppearWhenFinished)
{
	const fs::path dir = test::freshTempDir("pose_output");
	const fs::path file = dir / "poses.jsonl";
	auto out = PoseOutput::open("file:" + file.string(), nullptr);
	ASSERT_TRUE(out.ok());
	PoseEstimate e;
	e.found = true;
	e.pose.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
	e.pose.t = Eigen::Vector3d(-12.345678901234, 0.1, 987.654321);
	e.confidence = 0.8125f;
	e.score.score = 0.875f;
	e.margin = 0.09375f;
	e.iterationsDone = 5;
	e.bestIteration = 3;
	PoseLine line{42, 20, &e, 12.3456, 7.0};
	ASSERT_TRUE((*out)->writePose(line).ok());
	ASSERT_TRUE((*out)->writeError(42, -1, "quote \" and \\ and \n").ok());
	EXPECT_FALSE(fs::exists(file)); // only after finish()
	ASSERT_TRUE((*out)->finish().ok());

	std::ifstream in(file);
	std::string l1, l2;
	std::getline(in, l1);
	std::getline(in, l2);
	auto j = nlohmann::json::parse(l1);
	EXPECT_EQ(j["frame"], 42);
	EXPECT_EQ(j["obj_id"], 20);
	for (int i = 0; i < 9; ++i)
		EXPECT_EQ(j["R"][i].get<double>(), e.pose.R(i / 3, i % 3)); // bit-exact round trip
	EXPECT_EQ(j["t"][0].get<double>(), -12.345678901234);
	EXPECT_EQ(j["confidence"].get<double>(), 0.8125);
	EXPECT_EQ(j["score"].get<double>(), 0.875);
	EXPECT_EQ(j["margin"].get<double>(), 0.09375);
	EXPECT_EQ(j["iterations"], 5);
	EXPECT_EQ(j["best_iteration"], 3);
	EXPECT_EQ(j["latency_ms"].get<double>(), 12.346);
	auto k = nlohmann::json::parse(l2);
	EXPECT_EQ(k["error"], "quote \" and \\ and \n");
	EXPECT_FALSE(k.contains("obj_id"));
}

} // namespace
} // namespace ihf::app
