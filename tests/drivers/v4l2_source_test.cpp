// SPDX-License-Identifier: MIT
// The V4L2 source on this machine (no video device): URI parsing, and the
// errors for a missing node and for a file that is not a V4L2 device. The
// capture itself is tested against the kernel's vivid driver in a VM
// (v4l2_vivid_test.cpp).

#include <gtest/gtest.h>

#include "drivers/source_factory.h"
#include "drivers/v4l2_source.h"

namespace ihf {
namespace {

TEST(V4l2Uri, ParsesEveryKey)
{
	auto u = parseV4l2Uri("/dev/video3?format=z16&width=640&height=480&fps=30&buffers=6&scale=0.125&hfov=70");
	ASSERT_TRUE(u.ok()) << u.error().message;
	EXPECT_EQ(u->device, "/dev/video3");
	EXPECT_EQ(u->options.format, V4l2DepthFormat::kZ16);
	EXPECT_EQ(u->options.width, 640);
	EXPECT_EQ(u->options.height, 480);
	EXPECT_EQ(u->options.fps, 30);
	EXPECT_EQ(u->options.buffers, 6);
	EXPECT_EQ(u->options.scale, 0.125);
	EXPECT_EQ(u->options.hfovDeg, 70.0);
	EXPECT_FALSE(u->options.intrinsics.has_value());

	auto k = parseV4l2Uri("/dev/video0?fx=570.5&fy=571&cx=319.5&cy=239.5");
	ASSERT_TRUE(k.ok());
	ASSERT_TRUE(k->options.intrinsics.has_value());
	EXPECT_EQ(k->options.intrinsics->fx, 570.5);
	EXPECT_EQ(k->options.intrinsics->cy, 239.5);
	EXPECT_EQ(k->options.format, V4l2DepthFormat::kAuto);

	auto plain = parseV4l2Uri("/dev/video1");
	ASSERT_TRUE(plain.ok());
	EXPECT_EQ(plain->device, "/dev/video1");
}

TEST(V4l2Uri, BadUrisAreRefusedNamingTheKey)
{
	auto e = parseV4l2Uri("/dev/video0?format=rgb");
	ASSERT_FALSE(e.ok());
	EXPECT_NE(e.error().message.find("'format'"), std::string::npos);
	e = parseV4l2Uri("/dev/video0?colour=1");
	ASSERT_FALSE(e.ok());
	EXPECT_NE(e.error().message.find("unknown key 'colour'"), std::string::npos);
	e = parseV4l2Uri("/dev/video0?fx=500");
	ASSERT_FALSE(e.ok());
	EXPECT_NE(e.error().message.find("fx, fy, cx, cy"), std::string::npos);
	EXPECT_FALSE(parseV4l2Uri("/dev/video0?width=-5").ok());
	EXPECT_FALSE(parseV4l2Uri("/dev/video0?scale=0").ok());
	EXPECT_FALSE(parseV4l2Uri("?fps=30").ok());
	EXPECT_FALSE(makeFrameSource("v4l2:/dev/video0?buffers=1").ok());
	EXPECT_TRUE(makeFrameSource("v4l2:/dev/video0").ok()); // made unopened
}

TEST(V4l2Source, MissingNodeAndNonV4l2FileGiveClearErrors)
{
	V4l2Source missing("/dev/video-ihf-absent");
	Status s = missing.open();
	ASSERT_FALSE(s.ok());
	EXPECT_EQ(s.error().code, Errc::kNotFound);
	EXPECT_NE(s.error().message.find("/dev/video-ihf-absent"), std::string::npos) << s.error().message;
	EXPECT_NE(s.error().message.find("unplugged"), std::string::npos) << s.error().message;

	V4l2Source notV4l2("/dev/null");
	s = notV4l2.open();
	ASSERT_FALSE(s.ok());
	EXPECT_EQ(s.error().code, Errc::kUnsupported);
	EXPECT_NE(s.error().message.find("not a V4L2 device"), std::string::npos) << s.error().message;

	Frame f;
	EXPECT_FALSE(notV4l2.start().ok());
	EXPECT_FALSE(notV4l2.next(f, std::chrono::milliseconds(1)).ok());
}

} // namespace
} // namespace ihf
