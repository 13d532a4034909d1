// SPDX-License-Identifier: MIT
#pragma once

// Non-owning 2D views over caller buffers, and an owning image for the
// offline tools. Row-major, stride in elements.

#include <cstdint>
#include <span>
#include <vector>

namespace ihf {

template<typename T>
struct ImageView {
	T *data = nullptr;
	int width = 0;
	int height = 0;
	int stride = 0; // elements between row starts

	ImageView() = default;
	ImageView(T *d, int w, int h, int s = 0) : data(d), width(w), height(h), stride(s ? s : w) {}

	T &at(int x, int y) const { return data[static_cast<std::ptrdiff_t>(y) * stride + x]; }
	T *row(int y) const { return data + static_cast<std::ptrdiff_t>(y) * stride; }
	bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
	bool empty() const { return width <= 0 || height <= 0; }

	void fill(T value) const
	{
		for (int y = 0; y < height; ++y)
			for (int x = 0; x < width; ++x)
				at(x, y) = value;
	}

	operator ImageView<const T>() const { return {data, width, height, stride}; }
};

template<typename T>
class Image
{
public:
	Image() = default;
	Image(int width, int height, T init = T{})
		: width_(width), height_(height), data_(static_cast<size_t>(width) * height, init) {}

	int width() const { return width_; }
	int height() const { return height_; }
	bool empty() const { return data_.empty(); }
	T &at(int x, int y) { return data_[static_cast<size_t>(y) * width_ + x]; }
	const T &at(int x, int y) const { return data_[static_cast<size_t>(y) * width_ + x]; }
	T *data() { return data_.data(); }
	const T *data() const { return data_.data(); }
	std::span<T> pixels() { return data_; }
	std::span<const T> pixels() const { return data_; }

	ImageView<T> view() { return {data_.data(), width_, height_, width_}; }
	ImageView<const T> view() const { return {data_.data(), width_, height_, width_}; }

private:
	int width_ = 0;
	int height_ = 0;
	std::vector<T> data_;
};

// Raw sensor depth (units of depth_scale) and metric depth in millimetres.
using DepthImage16 = Image<uint16_t>;
using DepthImageMm = Image<float>;

} // namespace ihf
