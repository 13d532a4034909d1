// SPDX-License-Identifier: MIT
#include "core/estimation/estimator_workspace.h"

#include <algorithm>

#include "core/estimation/forest_walker.h"
#include "core/estimation/icp_polisher.h"

namespace ihf {

namespace {

IbsLimits ibsLimits(const EstimatorLimits &limits)
{
	IbsLimits ibs;
	ibs.maxN = limits.maxIbsN;
	ibs.maxPoints = limits.maxIbsPoints;
	ibs.maxActive = limits.maxActive;
	ibs.threads = WorkerPool::resolve(limits.threads);
	return ibs;
}

PartLimits partLimits(const EstimatorLimits &limits)
{
	PartLimits pl;
	pl.maxPoints = limits.maxWindowPixels;
	pl.maxControlPoints = limits.maxActive;
	pl.maxBoxPixels = limits.maxWindowPixels;
	return pl;
}

size_t count(int n)
{
	return static_cast<size_t>(std::max(n, 0));
}

} // namespace

template<typename A>
bool EstimatorWorkspace::carvePersistent(A &arena)
{
	const EstimatorLimits &l = limits_;
	const size_t threads = static_cast<size_t>(WorkerPool::resolve(l.threads));
	VoteBuffers &v = votes_;
	return arenaTake(arena, observed_, count(l.maxWindowPixels)) &&
	       arenaTake(arena, v.active, count(l.maxActive)) && arenaTake(arena, v.parts, count(l.maxParts)) &&
	       arenaTake(arena, v.pool, count(l.maxParts) * count(l.maxPartControlPoints)) &&
	       arenaTake(arena, v.hist, kMaxHistogramSlots * count(l.maxHistogramDims) * threads) &&
	       arenaTake(arena, v.votes, count(l.maxVotes)) && arenaTake(arena, v.modeScratch, count(l.maxVotes)) &&
	       arenaTake(arena, v.modeSupport, count(l.maxVotes)) && arenaTake(arena, v.modePacked, count(l.maxVotes)) &&
	       arenaTake(arena, v.modeThreadScratch, (threads - 1) * count(l.maxVotes)) &&
	       arenaTake(arena, v.modeThreadSupport, (threads - 1) * count(l.maxVotes)) &&
	       arenaTake(arena, v.seeds, count(l.maxModeSeeds)) && arenaTake(arena, v.modes, count(l.maxModes)) &&
	       arenaTake(arena, slabs_.hist, size_t{1024}) && arenaTake(arena, slabs_.windows, size_t{8}) &&
	       arenaTake(arena, slabs_.anchorWindows, size_t{4}) &&
	       arenaTake(arena, viewHeaps_, viewSearchHeapSize(static_cast<int>(threads))) &&
	       arenaTake(arena, viewFine_, size_t{kMaxCoarseKeep}) &&
	       arenaTake(arena, kept_, count(std::max(1, l.maxCandidates))) &&
	       arenaTake(arena, registrationKept_, count(std::max(1, l.maxCandidates))) &&
	       arenaTake(arena, rivals_, count(l.maxRivals)) &&
	       arenaTake(arena, partObserved_, count(l.maxWindowPixels)) &&
	       arenaTake(arena, partReference_, count(l.maxWindowPixels)) &&
	       arenaTake(arena, partRender_, count(l.maxWindowPixels) * threads);
}

template<typename A>
bool EstimatorWorkspace::carveBox(A &arena, size_t pixels)
{
	// One render buffer, and for the other threads' polishes one mask and
	// one cloud, per pool thread.
	const size_t others = static_cast<size_t>(WorkerPool::resolve(limits_.threads) - 1);
	return arenaTake(arena, working_, pixels) && arenaTake(arena, render_, pixels * (others + 1)) &&
	       arenaTake(arena, moreWorking_, pixels * others) && arenaTake(arena, moreClouds_, pixels * others) &&
	       arenaTake(arena, cloud_, pixels) && arenaTake(arena, unit_, pixels) &&
	       arenaTake(arena, normals_, pixels) && arenaTake(arena, reference_, pixels);
}

size_t EstimatorWorkspace::arenaBytes(const EstimatorLimits &limits)
{
	// The carve functions only record sizes on an ArenaSizer; a workspace
	// without an arena provides the members to carve into.
	ArenaSizer sizer;
	EstimatorWorkspace sizing(limits, SizingOnly{});
	sizing.carvePersistent(sizer);
	sizing.carveBox(sizer, count(limits.maxWindowPixels));
	return sizer.bytes + IbsFitter::arenaBytes(ibsLimits(limits)) + PartExtractor::arenaBytes(partLimits(limits)) +
	       DepthRenderer::arenaBytes(limits.maxMeshVertices) * static_cast<size_t>(WorkerPool::resolve(limits.threads));
}

EstimatorWorkspace::EstimatorWorkspace(const EstimatorLimits &limits, SizingOnly) : limits_(limits) {}

EstimatorWorkspace::EstimatorWorkspace(const EstimatorLimits &limits) : limits_(limits), workers_(limits.threads)
{
	auto arena = Arena::create(arenaBytes(limits));
	if (!arena)
		return;
	arena_ = std::move(*arena);
	valid_ = fitter_.reserve(ibsLimits(limits), arena_).ok() && extractor_.reserve(partLimits(limits), arena_).ok() &&
		 renderers_[0].reserve(limits.maxMeshVertices, arena_).ok() && carvePersistent(arena_);
	for (int t = 1; t < workers_.threads() && valid_; ++t)
		valid_ = renderers_[static_cast<size_t>(t)].reserve(limits.maxMeshVertices, arena_).ok();
	persistentBytes_ = arena_.used();
}

void EstimatorWorkspace::setCulling(bool cull)
{
	for (DepthRenderer &r : renderers_)
		r.setCullBackFaces(cull);
}

bool EstimatorWorkspace::beginBox(int w, int h)
{
	const size_t pixels = static_cast<size_t>(w) * h;
	if (!carveBox(arena_, pixels))
		return false;
	observedView_ = ImageView<float>(observed_.data(), w, h, w);
	workingView_ = ImageView<float>(working_.data(), w, h, w);
	referenceView_ = ImageView<float>(reference_.data(), w, h, w);
	return true;
}

void EstimatorWorkspace::endBox()
{
	working_ = render_ = moreWorking_ = {};
	moreClouds_ = cloud_ = {};
	unit_ = normals_ = {};
	reference_ = {};
	referenceView_ = {};
}

void EstimatorWorkspace::maskToRange(float nearMm, float farMm)
{
	cutToDepthRange(observedView_, nearMm, farMm, working_);
}

void EstimatorWorkspace::maskAll()
{
	std::copy_n(observed_.data(), static_cast<size_t>(observedView_.width) * observedView_.height, working_.data());
}

ImageView<float> EstimatorWorkspace::partReference(int w, int h) const
{
	return ImageView<float>(partReference_.data(), w, h, w);
}

ImageView<float> EstimatorWorkspace::partRender(int slot, int w, int h) const
{
	const size_t pixels = static_cast<size_t>(w) * h;
	return ImageView<float>(partRender_.data() + pixels * static_cast<size_t>(std::max(0, slot)), w, h, w);
}

WorkSlot EstimatorWorkspace::slot(int slot)
{
	const int w = observedView_.width, h = observedView_.height;
	const size_t pixels = static_cast<size_t>(w) * h;
	const size_t s = static_cast<size_t>(std::max(0, slot));
	WorkSlot out;
	out.renderer = &renderers_[s];
	out.render = ImageView<float>(render_.data() + pixels * s, w, h, w);
	out.mask = s == 0 ? working_.first(pixels) : moreWorking_.subspan(pixels * (s - 1), pixels);
	out.cloud = s == 0 ? cloud_.first(pixels) : moreClouds_.subspan(pixels * (s - 1), pixels);
	return out;
}

} // namespace ihf
