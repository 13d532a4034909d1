// SPDX-License-Identifier: MIT
#include "core/estimation/part_window.h"

#include <algorithm>

namespace ihf {

void PartWindow::cropFiner(ImageView<const float> frame, const CameraIntrinsics &frameK, const PixelBox &box,
			   int downsample, int pixels)
{
	const std::span<float> buffer = workspace_.partCropBuffer();
	const size_t limit = std::min(buffer.size(), static_cast<size_t>(std::max(pixels, 0)));
	const size_t boxPixels = static_cast<size_t>(box_.K.width) * box_.K.height;
	if (downsample <= 1 || limit <= boxPixels)
		return;
	VirtualCrop crop;
	if (makeVirtualCrop(frame, frameK, box, buffer.first(limit), crop) != CropStatus::kOk)
		return;
	// No finer after all (the box's window was cut by a whole factor as
	// this one is): the box's window serves.
	if (static_cast<size_t>(crop.intrinsics.width) * crop.intrinsics.height <= boxPixels)
		return;
	finer_ = true;
	K_ = crop.intrinsics;
	observed_ = crop.depth;
	validPixels_ = crop.validPixels;
}

double PartWindow::fineness() const
{
	if (!finer_)
		return 1.0;
	return static_cast<double>(K_.width) * K_.height / (static_cast<double>(box_.K.width) * box_.K.height);
}

ImageView<float> PartWindow::rendered(int slot)
{
	return finer_ ? workspace_.partRender(slot, K_.width, K_.height) : workspace_.slot(slot).render;
}

ImageView<float> PartWindow::reference()
{
	return finer_ ? workspace_.partReference(K_.width, K_.height) : workspace_.reference();
}

bool PartWindow::render(const Pose &pose, int slot)
{
	return renderModel(*workspace_.slot(slot).renderer, rendered(slot), model_, pose, intrinsics());
}

} // namespace ihf
