// SPDX-License-Identifier: MIT
#include "core/synth/household_objects.h"

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "core/synth/solid_builder.h"

namespace ihf {

namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

constexpr std::array kObjects{HouseholdObject::kCup, HouseholdObject::kCamera, HouseholdObject::kBottle};
constexpr std::array<std::string_view, 3> kNames{"cup", "camera", "bottle"};

} // namespace

Mesh makeCup(bool withPart)
{
	constexpr double foot = 36, rim = 42, height = 95, wall = 4;
	// Outer wall up, over the rim, inner wall down to a 4 mm thick floor.
	const std::array profile{V2(0, 0), V2(foot - 2, 0), V2(foot, 2), V2(rim, height),
				 V2(rim - wall, height), V2(foot - wall, wall), V2(0, wall)};
	Mesh cup = makeLathe(profile, 64);
	if (!withPart)
		return cup;
	// The handle: a C in the xz plane, its ends sunk into the wall. The wall's
	// radius at height z is foot + (rim - foot) z / height.
	constexpr double zMid = 52, reach = 26, halfSpan = 28, tube = 6;
	std::vector<V3> path;
	constexpr int steps = 24;
	for (int i = 0; i <= steps; ++i) {
		const double a = -std::numbers::pi / 2 + std::numbers::pi * i / steps;
		const double z = zMid + halfSpan * std::sin(a);
		const double wallR = foot + (rim - foot) * z / height;
		path.emplace_back(wallR - 3 + reach * std::cos(a), 0, z);
	}
	appendMesh(cup, makeTube(path, tube, V3::UnitY(), 16));
	return cup;
}

Mesh makeCamera(bool withPart)
{
	constexpr double w = 124, d = 68, h = 82;
	Mesh camera = makeSolidBox(V3(-w / 2, -d / 2, 0), V3(w / 2, d / 2, h));
	if (!withPart)
		return camera;
	// The lens: a barrel with a wider front ring, about -y, centred at
	// x = +14, z = 40; it starts inside the body.
	const std::array lensProfile{V2(0, 0), V2(30, 0), V2(30, 36), V2(33, 36), V2(33, 46), V2(0, 46)};
	Mesh lens = makeLathe(lensProfile, 48);
	transformMesh(lens, Eigen::AngleAxisd(std::numbers::pi / 2, V3::UnitX()).toRotationMatrix(),
		      V3(14, -d / 2 + 4, 40));
	appendMesh(camera, lens);
	// The strap lug on top at -x and the shutter button at +x.
	appendMesh(camera, makeSolidBox(V3(-w / 2 + 4, -5, h - 2), V3(-w / 2 + 14, 5, h + 10)));
	const std::array buttonProfile{V2(0, 0), V2(7, 0), V2(7, 7), V2(0, 7)};
	Mesh button = makeLathe(buttonProfile, 24);
	transformMesh(button, Eigen::Matrix3d::Identity(), V3(w / 2 - 22, -12, h - 1));
	appendMesh(camera, button);
	return camera;
}

Mesh makeBottle(bool withPart)
{
	// An upright body of revolution flattened to an oval.
	const std::array profile{V2(0, 0), V2(44, 0), V2(48, 4), V2(48, 150), V2(40, 164), V2(14, 172),
				 V2(14, 184), V2(0, 184)};
	Mesh bottle = makeLathe(profile, 64);
	transformMesh(bottle, Eigen::Vector3d(1.0, 28.0 / 48.0, 1.0).asDiagonal(), V3::Zero());
	// The pump: a stem, a head and the nozzle out towards +x.
	const std::array stemProfile{V2(0, 180), V2(6, 180), V2(6, 198), V2(0, 198)};
	appendMesh(bottle, makeLathe(stemProfile, 24));
	const std::array headProfile{V2(0, 196), V2(15, 196), V2(15, 212), V2(0, 212)};
	appendMesh(bottle, makeLathe(headProfile, 32));
	if (withPart)
		appendMesh(bottle, makeSolidBox(V3(10, -5, 201), V3(46, 5, 210)));
	return bottle;
}

Mesh makeHouseholdObject(HouseholdObject object, bool withPart)
{
	switch (object) {
	case HouseholdObject::kCup:
		return makeCup(withPart);
	case HouseholdObject::kCamera:
		return makeCamera(withPart);
	case HouseholdObject::kBottle:
		return makeBottle(withPart);
	}
	return {};
}

std::optional<HouseholdObject> householdObjectNamed(std::string_view name)
{
	for (size_t i = 0; i < kObjects.size(); ++i)
		if (kNames[i] == name)
			return kObjects[i];
	return std::nullopt;
}

std::string_view householdObjectName(HouseholdObject object)
{
	return kNames[static_cast<size_t>(object)];
}

std::span<const HouseholdObject> householdObjects()
{
	return kObjects;
}

} // namespace ihf
