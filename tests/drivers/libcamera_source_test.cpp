// SPDX-License-Identifier: MIT
// The libcamera source on a machine without a camera: its URI, and the
// clear error open() gives. Capture itself needs a camera (see docs/device.md).

#include <gtest/gtest.h>

#include "drivers/libcamera_source.h"
#include "drivers/source_factory.h"

namespace ihf {
namespace {

TEST(LibcameraUri, ParsesIdAndKeys)
{
	auto u = parseLibcameraUri("/base/soc/i2c0mux/i2c@1/imx219@10?width=640&height=480&scale=0.25&hfov=70&buffers=6");
	ASSERT_TRUE(u.ok()) << u.error().message;
	EXPECT_EQ(u->cameraId, "/base/soc/i2c0mux/i2c@1/imx219@10");
	EXPECT_EQ(u->options.width, 640);
	EXPECT_EQ(u->options.height, 480);
	EXPECT_EQ(u->options.scale, 0.25);
	EXPECT_EQ(u->options.hfovDeg, 70.0);
	EXPECT_EQ(u->options.buffers, 6);
	auto first = parseLibcameraUri("");
	ASSERT_TRUE(first.ok());
	EXPECT_TRUE(first->cameraId.empty());
	auto k = parseLibcameraUri("cam?fx=200&fy=201&cx=111.5&cy=85.5");
	ASSERT_TRUE(k.ok());
	ASSERT_TRUE(k->options.intrinsics.has_value());
	EXPECT_EQ(k->options.intrinsics->fy, 201.0);

	auto bad = parseLibcameraUri("cam?gain=3");
	ASSERT_FALSE(bad.ok());
	EXPECT_NE(bad.error().message.find("unknown key 'gain'"), std::string::npos);
	EXPECT_FALSE(parseLibcameraUri("cam?scale=-1").ok());
	EXPECT_FALSE(parseLibcameraUri("cam?fx=200").ok());
	EXPECT_TRUE(makeFrameSource("libcamera:").ok());
}

TEST(LibcameraSource, NoCameraGivesAClearError)
{
	auto cams = listLibcameraCameras();
	ASSERT_TRUE(cams.ok()) << cams.error().message;
	if (!cams->empty())
		GTEST_SKIP() << "this machine has a camera: " << cams->front();
	LibcameraSource src("");
	Status s = src.open();
	ASSERT_FALSE(s.ok());
	EXPECT_EQ(s.error().code, Errc::kNotFound);
	EXPECT_NE(s.error().message.find("libcamera:"), std::string::npos) << s.error().message;
	EXPECT_NE(s.error().message.find("no camera found"), std::string::npos) << s.error().message;
	Frame f;
	EXPECT_FALSE(src.start().ok());
	EXPECT_FALSE(src.next(f, std::chrono::milliseconds(1)).ok());

	LibcameraSource named("some/camera");
	s = named.open();
	ASSERT_FALSE(s.ok());
	EXPECT_NE(s.error().message.find("libcamera:some/camera"), std::string::npos) << s.error().message;
}

} // namespace
} // namespace ihf
