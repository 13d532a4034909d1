// SPDX-License-Identifier: MIT
#pragma once

// Normalisation of a cloud into the unit cube (Eq. 1-2):
//   X_N = (X - centre) / (s alpha) + 0.5,
// alpha the largest axis extent of the cloud and s >= 1 the scale-space
// factor (larger s, smaller object). The scaling is isotropic, so normals are
// the same in both frames. The frame is kept so that unit-cube results map
// back to camera millimetres.
//
// The paper centres on the mean; with a lopsided cloud that can push points
// out of [0, 1]^3 at s = 1, where the B-spline cannot hold them. The default
// therefore centres on the middle of the bounding box, which keeps every
// point inside for s >= 1; kMean is the paper's choice.

#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "core/common/expected.h"
#include "core/features/cloud_point.h"

namespace ihf {

enum class CubeCentre : uint8_t {
	kBoxCentre,
	kMean,
};

struct UnitCubeFrame {
	Eigen::Vector3f centre{0, 0, 0}; // camera mm, maps to (0.5, 0.5, 0.5)
	float alpha = 1.0f;              // largest axis extent of the cloud, mm
	float scale = 1.0f;              // s_i

	float mmPerUnit() const { return scale * alpha; }

	Eigen::Vector3f toUnit(const Eigen::Vector3f &cameraMm) const
	{
		return (cameraMm - centre) / mmPerUnit() + Eigen::Vector3f::Constant(0.5f);
	}

	Eigen::Vector3f toCamera(const Eigen::Vector3f &unit) const
	{
		return (unit - Eigen::Vector3f::Constant(0.5f)) * mmPerUnit() + centre;
	}

	UnitCubeFrame withScale(float s) const { return {centre, alpha, s}; }
};

// kInvalidArgument for an empty or degenerate (single point) cloud or s <= 0.
Expected<UnitCubeFrame> makeUnitCubeFrame(std::span<const CloudPoint> cloud, float scale = 1.0f,
					  CubeCentre centre = CubeCentre::kBoxCentre);

// Unit-cube positions and normals of the cloud, in the cloud's order;
// outPoints/outNormals must hold cloud.size() entries (outNormals may be
// empty when not wanted).
void toUnitCube(std::span<const CloudPoint> cloud, const UnitCubeFrame &frame,
		std::span<Eigen::Vector3f> outPoints, std::span<Eigen::Vector3f> outNormals = {});

// The object's scale h = max(Z_N) - min(Z_N) (Eq. 2).
float depthExtent(std::span<const Eigen::Vector3f> unitPoints);

} // namespace ihf
