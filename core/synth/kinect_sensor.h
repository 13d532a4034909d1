// SPDX-License-Identifier: MIT
#pragma once

// A Kinect v1 (PrimeSense structured light) depth sensor model applied to a
// clean rendered depth image. Each effect, in the order applied:
//  1. projector shadows: pixels the IR projector (baseline along +x) cannot
//     light get no depth (projector_shadow.h);
//  2. lateral jitter: depth is resampled at positions displaced by a
//     spatially correlated field of sigma_L = 0.8 + 0.035 theta/(pi/2 - theta)
//     pixels (Nguyen et al. 2012), which makes depth edges ragged;
//  3. foreground fattening: block matching lets the nearer surface bleed
//     0-2 px (mean 1) over the farther one at discontinuities;
//  4. axial noise: sigma_z = 1.2 mm + 1.9 mm (z_m - 0.4)^2, plus
//     0.1 mm / sqrt(z_m) theta^2 / (pi/2 - theta)^2 beyond 60 degrees of
//     incidence (Nguyen, Izadi, Lovell 2012, z in metres), spatially
//     correlated (the matcher's window);
//  5. disparity quantisation: d = b f / z rounded to 1/8 pixel, z = b f / d
//     (b = 75 mm, f = 580 px): ~2.9 mm steps at 1 m, ~11 mm at 2 m;
//  6. missing depth: grazing incidence (soft limit near ~80 degrees), part
//     of the pixels on depth edges, dark or shiny objects, small random blobs
//     and single pixels, the invalid band at the left image border, and
//     everything outside the 0.5-4 m range.

#include <cstdint>
#include <vector>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/synth/synth_random.h"

namespace ihf {

struct KinectParams {
	// Structured-light geometry (Kinect v1: Khoshelham & Elberink 2012).
	double baselineMm = 75.0;
	double focalPx = 580.0;  // IR camera focal length used for disparity
	double subpixel = 8.0;   // disparity steps per pixel
	// Axial noise (Nguyen et al. 2012), metres.
	double axialA = 0.0012;
	double axialB = 0.0019;
	double axialZ0 = 0.4;
	double axialGrazing = 0.0001;
	double noiseCorrelation = 0.9; // variance share of the correlated part
	int noiseRadius = 4;           // px: the matcher's ~9x9 window
	// Lateral noise (Nguyen et al. 2012), pixels.
	double lateralPx = 0.8;
	double lateralGrazing = 0.035;
	int lateralRadius = 2; // edges wobble over ~5 px, not per pixel
	double fatteningPx = 1.0; // mean bleed radius of the foreground
	// Edges and incidence.
	double edgeJumpMm = 15.0;
	double edgeJumpRel = 0.02;
	double edgeDropout = 0.15;      // share of edge pixels lost
	double maxIncidenceDeg = 80.0;  // no depth beyond
	double incidenceSoftDeg = 6.0;  // dropout ramps up over this span below
	// Random dropouts.
	double blobsPerImage = 6.0;
	double blobRadiusMax = 3.0;
	double pixelDropout = 0.0003;
	// Range (mm) and the invalid band at the left border (px).
	double minRangeMm = 500.0;
	double maxRangeMm = 4000.0;
	int leftBandMin = 4;
	int leftBandMax = 10;
	double shadowToleranceMm = 8.0;
};

struct SensorScene {
	ImageView<const float> depth;      // clean depth from the camera, mm
	ImageView<const uint16_t> label;   // object label per pixel (0 = none)
	ImageView<const float> projector;  // depth rendered from the projector
	int projectorX0 = 0;               // image column of projector pixel 0
	std::vector<float> labelDropout;   // per label: share of pixels lost
};

// Axial standard deviation (mm) at depth zMm and incidence theta (radians).
double kinectAxialSigmaMm(const KinectParams &p, double zMm, double theta);

// Depth after disparity quantisation (no noise).
double kinectQuantise(const KinectParams &p, double zMm);

// Quantisation step (mm) at depth zMm.
double kinectDepthStep(const KinectParams &p, double zMm);

// Sensor depth in units of depthScale mm (0 = no depth).
DepthImage16 simulateKinect(const SensorScene &scene, const CameraIntrinsics &K,
			    const KinectParams &p, SynthRandom &rng, double depthScale = 1.0);

} // namespace ihf
