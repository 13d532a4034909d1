// SPDX-License-Identifier: MIT
#pragma once

// Runs one peer over the given boxes of a BOP dataset the way `ihf estimate`
// runs the IHF: per box, the box's depth pixels are back-projected with the
// image's intrinsics (cloudFromDepth, camera-oriented normals) and handed to
// the peer. Writes a BOP results CSV (time = the image's summed box times)
// and a JSON with the per-box times and the model preparation times.

#include <string>
#include <vector>

#include "benchmarks/peers/peer.h"
#include "core/common/expected.h"

namespace ihf::peers {

struct PeerRunOptions {
	std::string dataset;
	std::string split;
	std::string boxes;
	std::vector<int> objects; // empty: every object that has a box
	std::string out;          // results CSV
	std::string statsJson;    // times, optional
	int modelPoints = 20000;  // surface samples per model
	uint32_t seed = 1;
	bool quiet = false;
};

struct PeerRunSummary {
	int boxes = 0;
	int poses = 0;
	int skipped = 0;
	std::vector<double> boxSeconds;
	std::vector<std::pair<int, double>> prepSeconds; // per object
};

Expected<PeerRunSummary> runPeer(Peer &peer, const PeerRunOptions &options);

} // namespace ihf::peers
