// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/vis_writer.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "core/dataset/bop_io.h"

namespace ihf::app {

Expected<std::unique_ptr<VisWriter>> VisWriter::create(const std::filesystem::path &dir,
						       const EstimatorLimits &limits)
{
	std::error_code ec;
	std::filesystem::create_directories(dir, ec);
	if (ec || !std::filesystem::is_directory(dir))
		return makeError(Errc::kIo, dir.string() + ": cannot create the --vis folder: " + ec.message());
	std::unique_ptr<VisWriter> v(new VisWriter());
	v->dir_ = dir;
	v->renderer_.reserve(limits.maxMeshVertices);
	return v;
}

void VisWriter::begin(uint64_t frame, int objId, const PixelBox &box, ImageView<const float>, const CameraIntrinsics &,
		      const ObjectModel &)
{
	frame_ = frame;
	objId_ = objId;
	box_ = box;
	best_.clear();
}

void VisWriter::onHypothesis(const HypothesisEvent &e)
{
	// The vote modes of each iteration; ICP's polish shows in the final picture.
	if (std::strcmp(e.stage, "mode") != 0 || e.iteration < 0)
		return;
	if (best_.size() <= static_cast<size_t>(e.iteration))
		best_.resize(e.iteration + 1);
	Best &b = best_[e.iteration];
	if (!b.valid || e.score.score > b.score) {
		b.valid = true;
		b.score = e.score.score;
		b.pose = e.pose;
	}
}

bool VisWriter::draw(ImageView<const float> depth, const CameraIntrinsics &K, const ObjectModel &model,
		     const Pose &pose, const uint8_t colour[3], const std::filesystem::path &file)
{
	// The box with a margin, clipped to the frame.
	const int mx = box_.w / 8 + 4, my = box_.h / 8 + 4;
	const int x0 = std::max(0, box_.x - mx), y0 = std::max(0, box_.y - my);
	const int x1 = std::min(depth.width, box_.x + box_.w + mx);
	const int y1 = std::min(depth.height, box_.y + box_.h + my);
	if (x1 <= x0 || y1 <= y0)
		return false;
	const int w = x1 - x0, h = y1 - y0;
	render_.assign(static_cast<size_t>(w) * h, 0.0f);
	ImageView<float> rv(render_.data(), w, h);
	if (!renderer_.render(model.mesh(), pose, K, rv, {}, 0, RenderWindow{x0, y0}))
		return false;

	float lo = 1e30f, hi = 0;
	for (int y = y0; y < y1; ++y)
		for (int x = x0; x < x1; ++x)
			if (const float d = depth.at(x, y); d > 0)
				lo = std::min(lo, d), hi = std::max(hi, d);
	const float span = hi > lo ? hi - lo : 1.0f;
	rgb_.assign(static_cast<size_t>(w) * h * 3, 0);
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			const float d = depth.at(x0 + x, y0 + y);
			uint8_t g = d > 0 ? static_cast<uint8_t>(235 - 200 * (d - lo) / span) : 0;
			uint8_t *p = &rgb_[(static_cast<size_t>(y) * w + x) * 3];
			p[0] = p[1] = p[2] = g;
			if (rv.at(x, y) <= 0)
				continue;
			const bool edge = x == 0 || y == 0 || x == w - 1 || y == h - 1 || rv.at(x - 1, y) <= 0 ||
					  rv.at(x + 1, y) <= 0 || rv.at(x, y - 1) <= 0 || rv.at(x, y + 1) <= 0;
			for (int c = 0; c < 3; ++c)
				p[c] = edge ? colour[c] : static_cast<uint8_t>((p[c] + colour[c]) / 2);
		}
	// The given box as a thin yellow frame.
	for (int x = box_.x; x < box_.x + box_.w; ++x)
		for (int y : {box_.y, box_.y + box_.h - 1})
			if (x >= x0 && x < x1 && y >= y0 && y < y1) {
				uint8_t *p = &rgb_[(static_cast<size_t>(y - y0) * w + (x - x0)) * 3];
				p[0] = 230, p[1] = 200, p[2] = 0;
			}
	for (int y = box_.y; y < box_.y + box_.h; ++y)
		for (int x : {box_.x, box_.x + box_.w - 1})
			if (x >= x0 && x < x1 && y >= y0 && y < y1) {
				uint8_t *p = &rgb_[(static_cast<size_t>(y - y0) * w + (x - x0)) * 3];
				p[0] = 230, p[1] = 200, p[2] = 0;
			}
	if (Status st = writePng8(file, w, h, 3, rgb_.data()); !st) {
		if (failure_.empty())
			failure_ = st.error().message;
		return false;
	}
	++written_;
	return true;
}

void VisWriter::end(ImageView<const float> depth, const CameraIntrinsics &K, const ObjectModel &model,
		    const PoseEstimate &estimate)
{
	static constexpr uint8_t kRed[3] = {230, 40, 40};
	static constexpr uint8_t kGreen[3] = {40, 220, 60};
	char name[96];
	for (size_t k = 0; k < best_.size(); ++k) {
		if (!best_[k].valid)
			continue;
		std::snprintf(name, sizeof(name), "f%06llu_o%d_it%zu.png", static_cast<unsigned long long>(frame_),
			      objId_, k);
		draw(depth, K, model, best_[k].pose, kRed, dir_ / name);
	}
	if (estimate.found) {
		std::snprintf(name, sizeof(name), "f%06llu_o%d_final.png", static_cast<unsigned long long>(frame_),
			      objId_);
		draw(depth, K, model, estimate.pose, kGreen, dir_ / name);
	}
}

} // namespace ihf::app
