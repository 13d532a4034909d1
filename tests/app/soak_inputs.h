// SPDX-License-Identifier: MIT
#pragma once

// Inputs for a soak of `ihf run`: a recording with corrupt frames mixed in,
// played looped (recording:PATH?loop=1), and the box lines of every pass
// with truncated lines and boxes of objects without a forest mixed in;
// beside them the clean inputs, what the run must see once the bad ones
// are skipped: the recording without the corrupt frames and the box lines
// without the truncated lines and the unknown objects' boxes. A run on the
// faulty inputs must give exactly the poses of a run on the clean ones and
// count every bad frame, line and box.
//
// From a recording and its box lines (one JSON line per frame, as
// `ihf synth --sequence` or `ihf record --boxes-out` write them) this writes
// into a folder:
//   faulty.rec, faulty.boxes.jsonl    the recording with every corruptEvery-th
//                                     frame damaged (payload, record header or
//                                     record magic in turn), box lines for
//                                     every pass
//   clean.rec, clean.boxes.jsonl      the same without the bad inputs
// The first and last frame are never damaged, so both recordings span the
// same frame indices and a looped run that stops after goodFrames frames
// has read every line and met every corrupt frame of every pass.

#include <cstdint>
#include <filesystem>

#include "core/common/expected.h"

namespace ihf::test {

struct SoakFaults {
	uint64_t passes = 1; // passes over the recording the box lines cover
	int corruptEvery = 0; // 0: no corrupt frames
	int truncateEvery = 0; // every n-th box line (over all passes) cut in the middle; 0: none
	int unknownEvery = 0; // every n-th box line gets a box of unknownObjId first; 0: none
	int unknownObjId = 999;
};

// What was written, and what a run over every pass must count.
struct SoakInputs {
	uint64_t recordsPerPass = 0;
	uint64_t corruptPerPass = 0;
	uint64_t indexSpan = 0; // what each pass adds to the frame indices
	uint64_t goodFrames = 0; // over every pass: the run's --frames
	uint64_t corruptFrames = 0; // corrupt frames met over every pass
	uint64_t lines = 0; // box lines written
	uint64_t truncatedLines = 0;
	uint64_t unknownBoxes = 0; // on intact lines of good frames: the ones the run meets
};

// The frames of a recording of `records` frames that makeSoakInputs damages.
uint64_t corruptFramesPerPass(uint64_t records, int corruptEvery);

Expected<SoakInputs> makeSoakInputs(const std::filesystem::path &recording, const std::filesystem::path &boxLines,
				    const SoakFaults &faults, const std::filesystem::path &outDir);

} // namespace ihf::test
