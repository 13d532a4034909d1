// SPDX-License-Identifier: MIT
// The procedural objects of the paper's kind: closed, outward, of their
// stated size, and their small part on one side only.

#include <gtest/gtest.h>

#include "core/geometry/mesh.h"
#include "core/synth/household_objects.h"

namespace ihf {
namespace {

TEST(HouseholdObjects, EveryObjectIsClosedAndOutward)
{
	for (HouseholdObject o : householdObjects()) {
		const Mesh m = makeHouseholdObject(o);
		EXPECT_TRUE(isClosedOutward(m)) << householdObjectName(o);
		EXPECT_EQ(countDegenerateFaces(m), 0u) << householdObjectName(o);
		EXPECT_NEAR(boundingBox(m).min.z(), 0.0f, 1e-4f) << householdObjectName(o);
	}
}

TEST(HouseholdObjects, NamesRoundTrip)
{
	for (HouseholdObject o : householdObjects())
		EXPECT_EQ(householdObjectNamed(householdObjectName(o)), o);
	EXPECT_FALSE(householdObjectNamed("kettle").has_value());
}

TEST(HouseholdObjects, SameMeshEveryTime)
{
	const Mesh a = makeCup(), b = makeCup();
	ASSERT_EQ(a.vertices.size(), b.vertices.size());
	for (size_t i = 0; i < a.vertices.size(); ++i)
		EXPECT_EQ(a.vertices[i], b.vertices[i]);
}

TEST(HouseholdObjects, CupHasItsSizeAndAHandleOnPlusXOnly)
{
	const Mesh m = makeCup();
	const Aabb box = boundingBox(m);
	EXPECT_NEAR(box.max.z(), 95.0f, 0.5f);
	// The body is 42 mm in radius at most: the handle alone reaches past it,
	// on +x and nowhere else.
	EXPECT_NEAR(box.min.x(), -42.0f, 0.5f);
	EXPECT_NEAR(box.min.y(), -42.0f, 0.5f);
	EXPECT_NEAR(box.max.y(), 42.0f, 0.5f);
	EXPECT_GT(box.max.x(), 42.0f + 20.0f);
	EXPECT_LT(box.max.x(), 42.0f + 40.0f);
}

TEST(HouseholdObjects, CameraHasItsLensOnMinusYAndItsLugOnTop)
{
	const Mesh m = makeCamera();
	const Aabb box = boundingBox(m);
	EXPECT_NEAR(box.min.x(), -62.0f, 0.1f);
	EXPECT_NEAR(box.max.x(), 62.0f, 0.1f);
	EXPECT_NEAR(box.max.y(), 34.0f, 0.1f); // the back is flat
	EXPECT_LT(box.min.y(), -34.0f - 40.0f); // the lens stands out in front
	EXPECT_GT(box.max.z(), 82.0f + 5.0f);  // lug and button stand on top
	// Only the lug stands on the top's -x half.
	for (const Eigen::Vector3f &v : m.vertices) {
		if (v.z() > 82.5f && v.x() < 0) {
			EXPECT_LT(v.x(), -40.0f);
		}
	}
}

TEST(HouseholdObjects, BottleHasItsNozzleOnPlusXOnly)
{
	const Mesh m = makeBottle();
	const Aabb box = boundingBox(m);
	EXPECT_NEAR(box.min.x(), -48.0f, 0.1f);
	EXPECT_NEAR(box.max.y(), 28.0f, 0.1f);
	EXPECT_NEAR(box.max.z(), 212.0f, 0.1f);
	for (const Eigen::Vector3f &v : m.vertices) {
		if (v.z() > 190.0f) {
			EXPECT_GT(v.x(), -15.5f); // nothing but the pump head on -x
		}
	}
	EXPECT_NEAR(box.max.x(), 48.0f, 0.1f); // the body, the nozzle stays inside it in x
}

} // namespace
} // namespace ihf
