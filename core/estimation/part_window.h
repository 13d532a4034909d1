// SPDX-License-Identifier: MIT
#pragma once

// The box at the resolution a nearly symmetric object's turns are compared
// at, pixel by pixel (symmetry_rivals.h; its close rivals, which differ
// over their silhouettes, are compared on the box's own window). The part
// that tells two turns apart, a handle or a lens, covers a few pixels of
// the box; inside a frame budget the box's window is downsampled so that
// its renders, scores and polish stay short, and the part then covers
// fewer still. cropFiner() crops the same box again from the frame, at up
// to the estimator's full window (the virtual camera is the box's, so a
// pose means the same in both); until then, or when that is no finer, the
// window is the box's own.

#include "core/common/image.h"
#include "core/estimation/estimator_workspace.h"
#include "core/estimation/pose_scorer.h"
#include "core/estimation/virtual_crop.h"

namespace ihf {

class PartWindow
{
public:
	// The box's window as scored, with its depth pixels.
	PartWindow(EstimatorWorkspace &workspace, const ObjectModel &model, const ScoreWindow &boxWindow,
		   int boxValidPixels)
		: workspace_(workspace), model_(model), box_(boxWindow), validPixels_(boxValidPixels)
	{
	}

	// The box cropped again from `frame` at up to `pixels`, if that is
	// finer than its window (downsampled by `downsample`). The frame must
	// outlive the box.
	void cropFiner(ImageView<const float> frame, const CameraIntrinsics &frameK, const PixelBox &box,
		       int downsample, int pixels);
	// Whether the window is a finer crop than the box's.
	bool finer() const { return finer_; }

	// The window's observed depth (mm, 0 = none), intrinsics and depth
	// pixels (the unit of its comparisons' cost).
	ImageView<const float> observed() const { return finer_ ? ImageView<const float>(observed_) : box_.observed; }
	const CameraIntrinsics &intrinsics() const { return finer_ ? K_ : box_.K; }
	int validPixels() const { return validPixels_; }
	// How many of its pixels one pixel of the box's window covers (1 when
	// it is the box's window).
	double fineness() const;
	// The pose rendered on `slot` (0: the caller's thread) into
	// rendered(slot); false if the render failed.
	bool render(const Pose &pose, int slot);
	ImageView<float> rendered(int slot);
	// A render kept while others are made on the slots.
	ImageView<float> reference();

private:
	EstimatorWorkspace &workspace_;
	const ObjectModel &model_;
	ScoreWindow box_;
	int validPixels_ = 0;
	bool finer_ = false;
	CameraIntrinsics K_;
	ImageView<float> observed_;
};

} // namespace ihf
