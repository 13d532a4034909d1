// SPDX-License-Identifier: MIT
#pragma once

// Extraction of parts from a fitted cloud (Sect. III-A, NOTES 4). Centres are
// cloud points on a pixel grid of the configured stride. A part's region is
//  - fixed: a window of g x (image box of the cloud) pixels around the centre
//    pixel; its control points are those that project into the window;
//  - variable: a cube of fixed side in the unit cube around the centre's
//    normalised point; its control points are those inside the cube.
// Either way the control points are limited along depth to the range of the
// part's own data points plus a margin, then capped to a maximum count, and
// stored relative to the centre with their HoCP keys set. The cap visits the
// control points in a per-frame priority order (a hash of the lattice index,
// or |weight|) and stops once it has enough, so large parts cost about
// cap x (all / in region) tests rather than a full scan.
//
// prepare() builds a pixel -> point map over the cloud's box and projects the
// control points once per frame; scratch is sized by reserve() and nothing is
// allocated afterwards (the scratch lives in an arena: the extractor's own,
// or one shared with the rest of the frame path). The spans given to
// prepare() must outlive extraction.

#include <array>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "core/common/expected.h"
#include "core/features/cloud_point.h"
#include "core/features/hocp.h"
#include "core/features/part.h"
#include "core/features/unit_cube_frame.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/ibs/control_point.h"
#include "core/runtime/arena.h"

namespace ihf {

struct PartSource {
	std::span<const CloudPoint> cloud;     // camera points with their pixels
	std::span<const Eigen::Vector3f> unit; // the same points in the unit cube
	std::span<const ControlPoint> cps;     // active control points of the fit
	UnitCubeFrame frame;                   // maps the unit cube to camera mm
	CameraIntrinsics intrinsics;           // needed by fixed parts only
	float latticeDelta = 0.0f;             // cell size of the fit, 1 / (N - 3)
};

struct PartLimits {
	int maxPoints = 20000;         // cloud points
	int maxControlPoints = 100000; // active control points
	int maxBoxPixels = 640 * 480;  // pixels of the cloud's image box
};

class PartExtractor
{
public:
	PartExtractor() = default;
	explicit PartExtractor(const PartLimits &limits) { reserve(limits); }

	// Sizes the scratch in an arena of the extractor's own (allocates); not
	// per frame.
	void reserve(const PartLimits &limits);
	// The same, carved from a shared arena that must outlive the extractor
	// (kCapacity if it is too small; the extractor then has no capacity).
	Status reserve(const PartLimits &limits, Arena &arena);
	static size_t arenaBytes(const PartLimits &limits);
	const PartLimits &limits() const { return limits_; }

	// Per frame: indexes the cloud's pixels and projects the control points.
	// kCapacity beyond the limits, kInvalidArgument on inconsistent input.
	Status prepare(const PartSource &source);

	// The image box of the cloud (the reference size of fixed parts).
	PixelBox cloudBox() const { return box_; }

	// Cloud indices of the part centres: valid pixels on a grid of
	// cfg.stride anchored at the box corner. Returns how many were written
	// (at most out.size()).
	int centres(const PartConfig &cfg, std::span<int32_t> out) const;

	// The part around cloud point `centre`; its control points go to
	// out[0 .. cpCount) (cpOffset is 0). out must hold cfg.maxControlPoints.
	Expected<Part> extract(int32_t centre, const PartConfig &cfg, const HocpConfig &hocp,
			       std::span<PartCp> out);

	// All parts on the centre grid with at least cfg.minDataPoints points;
	// control points are packed into pool, each part's cpOffset pointing at
	// its own. Stops with kCapacity when parts or pool run out.
	Expected<int> extractAll(const PartConfig &cfg, const HocpConfig &hocp,
				 std::span<Part> parts, std::span<PartCp> pool);

private:
	void dataRange(const Part &part, const PartConfig &cfg, int32_t &count, float &zLo,
		       float &zHi) const;

	template<typename A>
	bool carve(A &arena, const PartLimits &limits);

	PartLimits limits_;
	Arena own_; // used by reserve(limits) only
	PartSource src_;
	PixelBox box_;
	bool prepared_ = false;
	std::span<int32_t> pixelIndex_;        // box pixel -> cloud index, -1 if none
	std::span<Eigen::Vector2f> projected_; // control point -> pixel (fixed parts)
	void buildOrder(PartCap mode);

	static constexpr int kOrderBits = 12;
	std::span<int32_t> order_;             // control points in cap priority order
	std::array<int32_t, (1 << kOrderBits) + 1> bucketStart_{};
	PartCap orderMode_ = PartCap::kUniform;
	bool orderReady_ = false;
};

} // namespace ihf
