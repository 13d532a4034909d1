// SPDX-License-Identifier: MIT
#pragma once

// The estimator's memory and threads, all allocated at start-up (as
// TensorFlow Lite Micro's allocator): one arena sized from EstimatorLimits
// holds the persistent buffers at its bottom (the IBS fitter's, the part
// extractor's, the renderers', the votes', the kept hypotheses', the part
// window's) and, above them, the scratch of the current box, sized to its
// window and released after it. Each thread of the worker pool has a slot of its own (a
// renderer, a render buffer, a mask and a cloud), so that threads can score
// and polish side by side. Nothing is allocated per box.

#include <array>
#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "core/common/image.h"
#include "core/estimation/candidate_pool.h"
#include "core/estimation/depth_windows.h"
#include "core/features/cloud_point.h"
#include "core/features/part_extractor.h"
#include "core/ibs/ibs_fitter.h"
#include "core/pose/view_search.h"
#include "core/pose/vote_modes.h"
#include "core/render/depth_renderer.h"
#include "core/runtime/arena.h"
#include "core/runtime/worker_pool.h"

namespace ihf {

struct EstimatorLimits {
	int maxWindowPixels = 200 * 200;
	int maxParts = 3000;
	int maxPartControlPoints = 256;
	int maxVotes = 3000 * 3 * 16;
	int maxActive = 120000;
	int maxIbsPoints = 4000;
	int maxIbsN = 100;
	size_t maxMeshVertices = 50000;
	int maxHistogramDims = 1024; // HoCP length of the forests
	int maxModes = 32;           // vote modes per iteration (translation x rotation)
	int maxModeSeeds = 64;
	int maxCandidates = 16;      // distinct hypotheses kept over the iterations
	int maxRivals = 256;         // scored hypotheses kept for the confidence's margin (the best)
	int threads = 1;             // threads of a box's searches, the caller included (0: one per core)
};

// The Hough voter's persistent buffers.
struct VoteBuffers {
	std::span<ControlPoint> active;
	std::span<Part> parts;
	std::span<PartCp> pool;
	std::span<float> hist; // one histogram set per thread
	std::span<CastVote> votes;
	std::span<float> modeScratch;
	std::span<uint32_t> modeSupport;
	std::span<Eigen::Vector4f> modePacked;
	std::span<float> modeThreadScratch; // the other threads' (threads - 1 x maxVotes)
	std::span<uint32_t> modeThreadSupport;
	std::span<Eigen::Vector3f> seeds;
	std::span<PoseMode> modes;
};

// The depth slabs of a box (depth_windows.h).
struct SlabBuffers {
	std::span<int> hist;
	std::span<DepthWindow> windows;
	std::span<DepthWindow> anchorWindows; // the view search's own, when thinner
};

// What one thread scores and polishes with: its renderer and render
// buffer, and a mask and a cloud of the window's size.
struct WorkSlot {
	DepthRenderer *renderer = nullptr;
	ImageView<float> render;
	std::span<float> mask;
	std::span<CloudPoint> cloud;
};

class EstimatorWorkspace
{
public:
	// Allocates the arena and starts the pool's threads; valid() tells
	// whether the arena could be allocated and carved.
	explicit EstimatorWorkspace(const EstimatorLimits &limits);
	EstimatorWorkspace(const EstimatorWorkspace &) = delete;
	EstimatorWorkspace &operator=(const EstimatorWorkspace &) = delete;

	// Arena bytes for the limits: persistent buffers plus the scratch of a
	// box of maxWindowPixels.
	static size_t arenaBytes(const EstimatorLimits &limits);

	bool valid() const { return valid_; }
	const EstimatorLimits &limits() const { return limits_; }
	Arena &arena() { return arena_; }
	const Arena &arena() const { return arena_; }
	size_t persistentBytes() const { return persistentBytes_; }
	WorkerPool &workers() { return workers_; }
	int threads() const { return workers_.threads(); }

	IbsFitter &fitter() { return fitter_; }
	PartExtractor &extractor() { return extractor_; }
	VoteBuffers &votes() { return votes_; }
	SlabBuffers &slabs() { return slabs_; }
	ViewSearchWorkspace viewSearch() const { return {viewHeaps_, viewFine_}; }
	// The kept lists' and the rivals' storage handed to the pool.
	void attachPool(CandidatePool &pool) { pool.attach(kept_, registrationKept_, rivals_); }
	// The virtual crop's buffer (maxWindowPixels).
	std::span<float> cropBuffer() { return observed_; }

	// Every renderer skips back faces or draws them.
	void setCulling(bool cull);
	// The mesh vertices a renderer holds at most.
	size_t renderCapacity() const { return renderers_[0].capacity(); }
	DepthRenderer &renderer() { return renderers_[0]; }

	// The box's scratch, for a window of w x h pixels, carved from the arena
	// above the persistent buffers (the caller's ArenaScope releases it);
	// the observed view is the crop buffer's first w x h pixels. False if
	// the arena is too small.
	bool beginBox(int w, int h);
	// Forgets the box's spans (after the arena scope has rewound).
	void endBox();

	ImageView<float> observed() const { return observedView_; }
	// The box's mask (the crop cut to a depth range, Eq. 10) and cloud,
	// which the votes are cast from: slot 0's.
	ImageView<float> working() const { return workingView_; }
	// The working mask becomes the observed window cut to (nearMm, farMm).
	void maskToRange(float nearMm, float farMm);
	// and to the window copied whole.
	void maskAll();
	std::span<CloudPoint> cloud() { return cloud_; }
	std::span<Eigen::Vector3f> unit() { return unit_; }
	std::span<Eigen::Vector3f> normals() { return normals_; }
	// A render kept while others are made on the slots: the pose that
	// rivals are compared with pixel by pixel (symmetry_rivals.h).
	ImageView<float> reference() const { return referenceView_; }
	// A finer window of the box for those comparisons (part_window.h):
	// its crop buffer (maxWindowPixels), and its reference and slot
	// renders at w x h.
	std::span<float> partCropBuffer() { return partObserved_; }
	ImageView<float> partReference(int w, int h) const;
	ImageView<float> partRender(int slot, int w, int h) const;
	// Thread `slot`'s renderer and buffers (0: the caller's).
	WorkSlot slot(int slot);

private:
	template<typename A>
	bool carvePersistent(A &arena);
	template<typename A>
	bool carveBox(A &arena, size_t pixels);
	// No arena, no threads: the members to size for arenaBytes().
	struct SizingOnly {};
	EstimatorWorkspace(const EstimatorLimits &limits, SizingOnly);

	EstimatorLimits limits_;
	Arena arena_;
	bool valid_ = false;
	size_t persistentBytes_ = 0;
	WorkerPool workers_; // started with the arena, idle between searches
	IbsFitter fitter_;
	PartExtractor extractor_;
	std::array<DepthRenderer, WorkerPool::kMaxThreads> renderers_; // one per slot

	// Persistent (sized from the limits).
	std::span<float> observed_; // virtual crop
	VoteBuffers votes_;
	SlabBuffers slabs_;
	std::span<ViewCoarseCandidate> viewHeaps_; // the view search's, per thread
	std::span<ViewFineResult> viewFine_;
	std::span<Hypothesis> kept_, registrationKept_;
	std::span<RivalPose> rivals_;
	std::span<float> partObserved_, partReference_, partRender_; // part_window.h (one render per slot)

	// Per box (sized to its window).
	std::span<float> working_;
	std::span<float> render_;          // one window per slot
	std::span<float> reference_;
	std::span<float> moreWorking_;     // the other slots' masks (threads - 1 windows)
	std::span<CloudPoint> moreClouds_; // and clouds
	std::span<CloudPoint> cloud_;
	std::span<Eigen::Vector3f> unit_, normals_;
	ImageView<float> observedView_, workingView_, referenceView_;
};

} // namespace ihf
