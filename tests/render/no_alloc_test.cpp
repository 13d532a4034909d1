// SPDX-License-Identifier: MIT
// render() must not touch the heap once reserve() sized the scratch space:
// this executable replaces global operator new and counts calls while armed.

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include <gtest/gtest.h>

#include "core/render/depth_renderer.h"
#include "tests/render/test_shapes.h"

namespace {
std::atomic<bool> gArmed{false};
std::atomic<int> gAllocations{0};
} // namespace

void *operator new(std::size_t size)
{
	if (gArmed.load(std::memory_order_relaxed))
		gAllocations.fetch_add(1, std::memory_order_relaxed);
	if (void *p = std::malloc(size ? size : 1))
		return p;
	throw std::bad_alloc();
}

void operator delete(void *p) noexcept
{
	std::free(p);
}

void operator delete(void *p, std::size_t) noexcept
{
	std::free(p);
}

namespace ihf {
namespace {

TEST(DepthRendererMemory, RenderDoesNotAllocate)
{
	CameraIntrinsics K;
	K.fx = 572.4114;
	K.fy = 573.57043;
	K.cx = 325.2611;
	K.cy = 242.04899;
	K.width = 640;
	K.height = 480;
	const Mesh sphere = test::icosphere(50, 4);
	// Crosses the near plane too, so the clipping path runs.
	const Mesh floor = test::quad({-3000, 100, -1000}, {3000, 100, -1000}, {3000, 100, 3000}, {-3000, 100, 3000});
	Pose pose;
	pose.t = {0, 0, 600};

	DepthRenderer r(sphere.vertices.size());
	DepthImageMm depth(640, 480);
	Image<uint16_t> label(640, 480);
	DepthImageMm crop(160, 160);

	// The hook itself works.
	gAllocations = 0;
	gArmed = true;
	{
		std::vector<int> probe(100);
		probe[0] = 1;
	}
	gArmed = false;
	ASSERT_GE(gAllocations.load(), 1);

	gAllocations = 0;
	gArmed = true;
	auto a = r.render(floor, Pose{}, K, depth.view(), label.view(), 1);
	auto b = r.render(sphere, pose, K, depth.view(), label.view(), 2);
	auto c = r.render(sphere, pose, K, crop.view(), {}, 0, {250, 160});
	gArmed = false;

	ASSERT_TRUE(a.ok() && b.ok() && c.ok());
	EXPECT_GT(a->pixelsWritten, 1000);
	EXPECT_GT(b->pixelsWritten, 1000);
	EXPECT_GT(c->pixelsWritten, 1000);
	EXPECT_EQ(gAllocations.load(), 0);
}

} // namespace
} // namespace ihf
