// SPDX-License-Identifier: MIT
#pragma once

// A part (Sect. III-A, NOTES 4): a region around a centre pixel of the cloud
// and the active control points inside it, stored relative to the centre in
// unit-cube units so that the forest can re-histogram them cheaply.

#include <cstdint>

#include <Eigen/Core>

namespace ihf {

enum class PartKind : uint8_t {
	kFixed,    // window of g x (image box of the cloud) pixels
	kVariable, // cube of fixed side in the unit cube around the centre point
};

// How a part with more control points than the cap is thinned.
enum class PartCap : uint8_t {
	kUniform,       // a pseudo-random subset keyed on the lattice index
			//   (spatially uniform, stable when the region gains or
			//   loses a node)
	kLargestWeight, // the largest |weight|
};

struct PartConfig {
	PartKind kind = PartKind::kVariable;
	int stride = 4;                 // pixels between part centres
	float fixedFraction = 0.5f;     // g of fixed parts (paper g^0 = 1/2)
	float variableSide = 0.75f;     // cube side of variable parts, unit-cube units
	float depthMarginCells = 2.0f;  // control points kept within the data's
					//   depth range +- this many lattice cells
	int maxControlPoints = 256;     // per part, after the depth limit
	PartCap cap = PartCap::kUniform;
	int minDataPoints = 16;         // extractAll() skips sparser parts
	bool countAllControlPoints = false; // scan the whole region to fill
					    //   Part::cpTotal even past the cap
};

// One control point of a part. rel = node position - part centre (unit
// cube), rel.z() is the relative depth the depth check uses. logR and angBin
// are the HoCP keys (log radius and inclination/azimuth bin) precomputed by
// setHocpKeys(), so histograms need no transcendental per point.
struct PartCp {
	Eigen::Vector3f rel{0, 0, 0};
	float weight = 0;
	float logR = 0;
	uint16_t angBin = 0;
	uint16_t reserved = 0;
};

struct Part {
	int32_t point = -1;               // centre: index into the cloud
	int32_t u = 0, v = 0;             // centre pixel
	Eigen::Vector3f centreUnit{0, 0, 0};
	Eigen::Vector3f centreCamera{0, 0, 0}; // mm
	float zMin = 0, zMax = 0;         // depth range of the part's data points
					  //   relative to the centre, unit cube
	int32_t dataPoints = 0;           // cloud points inside the region
	int32_t cpTotal = 0;              // control points in the region; once the
					  //   cap is hit only counted on with
					  //   countAllControlPoints (else = cpCount)
	uint32_t cpOffset = 0;            // first control point in the pool
	uint32_t cpCount = 0;             // control points kept
};

} // namespace ihf
