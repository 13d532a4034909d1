// SPDX-License-Identifier: MIT

#include "core/features/part_extractor.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/features/depth_cloud.h"

namespace ihf {

namespace {

// Integer hash (the murmur3 finaliser): a uniform key per lattice node.
uint32_t mixIndex(int32_t index)
{
	uint32_t h = static_cast<uint32_t>(index);
	h ^= h >> 16;
	h *= 0x85ebca6bu;
	h ^= h >> 13;
	h *= 0xc2b2ae35u;
	h ^= h >> 16;
	return h;
}

} // namespace

template<typename A>
bool PartExtractor::carve(A &arena, const PartLimits &limits)
{
	const size_t cps = static_cast<size_t>(std::max(limits.maxControlPoints, 0));
	return arenaTake(arena, pixelIndex_, static_cast<size_t>(std::max(limits.maxBoxPixels, 0))) &&
	       arenaTake(arena, projected_, cps) && arenaTake(arena, order_, cps);
}

size_t PartExtractor::arenaBytes(const PartLimits &limits)
{
	ArenaSizer sizer;
	PartExtractor scratch;
	scratch.carve(sizer, limits);
	return sizer.bytes;
}

void PartExtractor::reserve(const PartLimits &limits)
{
	auto arena = Arena::create(arenaBytes(limits));
	if (!arena) {
		*this = PartExtractor();
		return;
	}
	own_ = std::move(*arena);
	(void)reserve(limits, own_);
}

Status PartExtractor::reserve(const PartLimits &limits, Arena &arena)
{
	prepared_ = false;
	orderReady_ = false;
	if (!carve(arena, limits)) {
		limits_ = PartLimits{0, 0, 0};
		pixelIndex_ = {};
		projected_ = {};
		order_ = {};
		return makeError(Errc::kCapacity, "PartExtractor: arena too small for the PartLimits");
	}
	limits_ = limits;
	std::fill(pixelIndex_.begin(), pixelIndex_.end(), -1);
	return {};
}

Status PartExtractor::prepare(const PartSource &source)
{
	prepared_ = false;
	if (source.unit.size() != source.cloud.size())
		return makeError(Errc::kInvalidArgument, "PartExtractor: cloud and unit points differ in size");
	if (!(source.latticeDelta > 0.0f))
		return makeError(Errc::kInvalidArgument, "PartExtractor: latticeDelta must be > 0");
	if (source.cloud.size() > static_cast<size_t>(limits_.maxPoints))
		return makeError(Errc::kCapacity, "PartExtractor: cloud exceeds PartLimits::maxPoints");
	if (source.cps.size() > static_cast<size_t>(limits_.maxControlPoints))
		return makeError(Errc::kCapacity, "PartExtractor: control points exceed PartLimits::maxControlPoints");

	src_ = source;
	box_ = cloudPixelBox(source.cloud);
	const size_t pixels = static_cast<size_t>(box_.w) * static_cast<size_t>(box_.h);
	if (pixels > pixelIndex_.size())
		return makeError(Errc::kCapacity, "PartExtractor: cloud box exceeds PartLimits::maxBoxPixels");
	std::fill_n(pixelIndex_.begin(), pixels, -1);
	for (size_t i = 0; i < source.cloud.size(); ++i) {
		const CloudPoint &c = source.cloud[i];
		pixelIndex_[static_cast<size_t>(c.v - box_.y) * box_.w + (c.u - box_.x)] =
			static_cast<int32_t>(i);
	}

	// Control points in pixels, for fixed parts. A node behind the camera
	// cannot be seen in any window.
	const CameraIntrinsics &k = source.intrinsics;
	const bool project = k.valid();
	const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
	const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
	for (size_t i = 0; i < source.cps.size(); ++i) {
		const Eigen::Vector3f p = source.frame.toCamera(source.cps[i].pos);
		if (project && p.z() > 0.0f)
			projected_[i] = {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
		else
			projected_[i] = Eigen::Vector2f::Constant(std::numeric_limits<float>::quiet_NaN());
	}
	orderReady_ = false;
	prepared_ = true;
	return {};
}

void PartExtractor::buildOrder(PartCap mode)
{
	const std::span<const ControlPoint> cps = src_.cps;
	const int32_t n = static_cast<int32_t>(cps.size());
	if (mode == PartCap::kUniform) {
		// Counting sort on the top bits of a hash of the lattice index;
		// within a bucket the (index-sorted) input order is kept. The
		// priority thus depends on the node alone.
		std::fill(bucketStart_.begin(), bucketStart_.end(), 0);
		for (int32_t i = 0; i < n; ++i)
			++bucketStart_[(mixIndex(cps[i].index) >> (32 - kOrderBits)) + 1];
		for (size_t b = 1; b < bucketStart_.size(); ++b)
			bucketStart_[b] += bucketStart_[b - 1];
		for (int32_t i = 0; i < n; ++i)
			order_[bucketStart_[mixIndex(cps[i].index) >> (32 - kOrderBits)]++] = i;
	} else {
		for (int32_t i = 0; i < n; ++i)
			order_[i] = i;
		std::sort(order_.begin(), order_.begin() + n, [&](int32_t a, int32_t b) {
			const float wa = std::abs(cps[a].weight), wb = std::abs(cps[b].weight);
			return wa > wb || (wa == wb && a < b);
		});
	}
	orderMode_ = mode;
	orderReady_ = true;
}

int PartExtractor::centres(const PartConfig &cfg, std::span<int32_t> out) const
{
	if (!prepared_ || cfg.stride < 1)
		return 0;
	int count = 0;
	for (int v = 0; v < box_.h; v += cfg.stride)
		for (int u = 0; u < box_.w; u += cfg.stride) {
			const int32_t idx = pixelIndex_[static_cast<size_t>(v) * box_.w + u];
			if (idx < 0)
				continue;
			if (count == static_cast<int>(out.size()))
				return count;
			out[count++] = idx;
		}
	return count;
}

namespace {

// Window of a fixed part in box coordinates, clipped; half extents in pixels.
struct Window {
	float u0, u1, v0, v1; // image pixels, inclusive bounds
};

Window fixedWindow(int u, int v, const PixelBox &box, float g)
{
	const float hw = 0.5f * g * static_cast<float>(box.w);
	const float hh = 0.5f * g * static_cast<float>(box.h);
	return {u - hw, u + hw, v - hh, v + hh};
}

} // namespace

void PartExtractor::dataRange(const Part &part, const PartConfig &cfg, int32_t &count,
			      float &zLo, float &zHi) const
{
	count = 0;
	zLo = std::numeric_limits<float>::max();
	zHi = std::numeric_limits<float>::lowest();
	const auto take = [&](int32_t i) {
		const float z = src_.unit[i].z();
		zLo = std::min(zLo, z);
		zHi = std::max(zHi, z);
		++count;
	};
	if (cfg.kind == PartKind::kFixed) {
		const Window w = fixedWindow(part.u, part.v, box_, cfg.fixedFraction);
		const int ua = std::max(static_cast<int>(std::ceil(w.u0)), box_.x);
		const int ub = std::min(static_cast<int>(std::floor(w.u1)), box_.x + box_.w - 1);
		const int va = std::max(static_cast<int>(std::ceil(w.v0)), box_.y);
		const int vb = std::min(static_cast<int>(std::floor(w.v1)), box_.y + box_.h - 1);
		for (int v = va; v <= vb; ++v) {
			const int32_t *row = &pixelIndex_[static_cast<size_t>(v - box_.y) * box_.w];
			for (int u = ua; u <= ub; ++u)
				if (row[u - box_.x] >= 0)
					take(row[u - box_.x]);
		}
	} else {
		const float h = 0.5f * cfg.variableSide;
		const Eigen::Vector3f &c = part.centreUnit;
		for (size_t i = 0; i < src_.unit.size(); ++i) {
			const Eigen::Vector3f &p = src_.unit[i];
			if (std::abs(p.x() - c.x()) <= h && std::abs(p.y() - c.y()) <= h &&
			    std::abs(p.z() - c.z()) <= h)
				take(static_cast<int32_t>(i));
		}
	}
}

Expected<Part> PartExtractor::extract(int32_t centre, const PartConfig &cfg,
				      const HocpConfig &hocp, std::span<PartCp> out)
{
	if (!prepared_)
		return makeError(Errc::kInvalidArgument, "PartExtractor: extract() before prepare()");
	if (centre < 0 || static_cast<size_t>(centre) >= src_.cloud.size())
		return makeError(Errc::kOutOfRange, "PartExtractor: centre index outside the cloud");
	if (cfg.maxControlPoints < 1 || out.size() < static_cast<size_t>(cfg.maxControlPoints))
		return makeError(Errc::kCapacity, "PartExtractor: output smaller than PartConfig::maxControlPoints");

	Part part;
	part.point = centre;
	part.u = src_.cloud[centre].u;
	part.v = src_.cloud[centre].v;
	part.centreUnit = src_.unit[centre];
	part.centreCamera = src_.cloud[centre].p;

	float zLo, zHi;
	dataRange(part, cfg, part.dataPoints, zLo, zHi);
	const Eigen::Vector3f &c = part.centreUnit;
	part.zMin = zLo - c.z();
	part.zMax = zHi - c.z();
	const float margin = cfg.depthMarginCells * src_.latticeDelta;
	const float zA = zLo - margin, zB = zHi + margin;

	// Control points in the region and the depth range, visited in the
	// cap's priority order so that the scan can stop at the cap.
	if (!orderReady_ || orderMode_ != cfg.cap)
		buildOrder(cfg.cap);
	const std::span<const ControlPoint> cps = src_.cps;
	const int cap = cfg.maxControlPoints;
	int kept = 0, total = 0;
	const auto visit = [&](auto inRegion) {
		for (size_t k = 0; k < cps.size(); ++k) {
			const int32_t i = order_[k];
			const float z = cps[i].pos.z();
			if (z < zA || z > zB || !inRegion(i))
				continue;
			++total;
			if (kept < cap) {
				out[kept++] = PartCp{cps[i].pos - c, cps[i].weight, 0.0f, 0, 0};
				if (kept == cap && !cfg.countAllControlPoints)
					break;
			}
		}
	};
	if (cfg.kind == PartKind::kFixed) {
		const Window w = fixedWindow(part.u, part.v, box_, cfg.fixedFraction);
		// NaN projections fail every comparison.
		visit([&](int32_t i) {
			const Eigen::Vector2f &px = projected_[i];
			return px.x() >= w.u0 && px.x() <= w.u1 && px.y() >= w.v0 && px.y() <= w.v1;
		});
	} else {
		const float h = 0.5f * cfg.variableSide;
		visit([&](int32_t i) {
			const Eigen::Vector3f d = cps[i].pos - c;
			return std::abs(d.x()) <= h && std::abs(d.y()) <= h && std::abs(d.z()) <= h;
		});
	}
	part.cpTotal = total;
	setHocpKeys(out.first(kept), hocp);
	part.cpCount = static_cast<uint32_t>(kept);
	part.cpOffset = 0;
	return part;
}

Expected<int> PartExtractor::extractAll(const PartConfig &cfg, const HocpConfig &hocp,
					std::span<Part> parts, std::span<PartCp> pool)
{
	if (!prepared_)
		return makeError(Errc::kInvalidArgument, "PartExtractor: extractAll() before prepare()");
	int count = 0;
	size_t used = 0;
	for (int v = 0; v < box_.h; v += std::max(cfg.stride, 1)) {
		for (int u = 0; u < box_.w; u += std::max(cfg.stride, 1)) {
			const int32_t idx = pixelIndex_[static_cast<size_t>(v) * box_.w + u];
			if (idx < 0)
				continue;
			if (count == static_cast<int>(parts.size()))
				return makeError(Errc::kCapacity, "PartExtractor: parts span full");
			if (pool.size() - used < static_cast<size_t>(cfg.maxControlPoints))
				return makeError(Errc::kCapacity, "PartExtractor: control point pool full");
			auto part = extract(idx, cfg, hocp, pool.subspan(used));
			if (!part)
				return part.error();
			if (part->dataPoints < cfg.minDataPoints || part->cpCount == 0)
				continue;
			part->cpOffset = static_cast<uint32_t>(used);
			used += part->cpCount;
			parts[count++] = *part;
		}
	}
	return count;
}

} // namespace ihf
