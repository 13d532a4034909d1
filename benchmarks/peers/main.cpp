// SPDX-License-Identifier: MIT
// ihf_peers: runs one peer method (OpenCV PPF, Open3D, PCL) over the given
// boxes of a BOP dataset, like `ihf estimate`, and writes a BOP results CSV
// plus the per-box and model preparation times. See docs/peers.md.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "benchmarks/peers/peer_runner.h"
#if IHF_PEER_OPENCV
#include "benchmarks/peers/peer_opencv_ppf.h"
#include <opencv2/core/utility.hpp>
#endif
#if IHF_PEER_OPEN3D
#include "benchmarks/peers/peer_open3d.h"
#endif
#if IHF_PEER_PCL
#include "benchmarks/peers/peer_pcl_fpfh.h"
#include "benchmarks/peers/peer_pcl_icp.h"
#endif

namespace {

std::vector<std::string> availablePeers()
{
	std::vector<std::string> names;
#if IHF_PEER_OPENCV
	names.push_back("opencv_ppf");
#endif
#if IHF_PEER_OPEN3D
	names.push_back("open3d_fpfh");
#endif
#if IHF_PEER_PCL
	names.push_back("pcl_icp");
	names.push_back("pcl_fpfh");
#endif
	return names;
}

std::unique_ptr<ihf::peers::Peer> makePeer(const std::string &name)
{
	using namespace ihf::peers;
#if IHF_PEER_OPENCV
	if (name == "opencv_ppf") {
		// One thread, like every other method here.
		cv::setNumThreads(1);
		return std::make_unique<OpenCvPpfPeer>(OpenCvPpfParams{});
	}
#endif
#if IHF_PEER_OPEN3D
	if (name == "open3d_fpfh")
		return std::make_unique<Open3dPeer>(Open3dParams{});
#endif
#if IHF_PEER_PCL
	if (name == "pcl_icp")
		return std::make_unique<PclIcpPeer>(PclIcpPeerParams{});
	if (name == "pcl_fpfh")
		return std::make_unique<PclFpfhPeer>(PclFpfhParams{});
#endif
	return nullptr;
}

} // namespace

int main(int argc, char **argv)
{
	ihf::peers::PeerRunOptions o;
	std::string peerName;
	bool list = false;
	CLI::App app{"Runs a peer pose estimator (OpenCV PPF, Open3D FPFH+RANSAC, PCL ICP or FPFH) on the "
		     "given boxes of a BOP dataset and writes a BOP results CSV"};
	app.add_flag("--list", list, "Print the peers built in and exit");
	app.add_option("--peer", peerName, "Peer to run (see --list)");
	app.add_option("--dataset", o.dataset, "BOP dataset folder")->check(CLI::ExistingDirectory);
	app.add_option("--split", o.split, "Split folder (default: test, val or train)");
	app.add_option("--boxes", o.boxes, "Given boxes (BOP detection JSON list)")->check(CLI::ExistingFile);
	app.add_option("--objects", o.objects, "Only boxes of these object ids, e.g. 1,5")->delimiter(',');
	app.add_option("--out", o.out, "Results CSV to write (BOP format)");
	app.add_option("--stats-json", o.statsJson, "Also write per-box and model preparation times as JSON");
	app.add_option("--model-points", o.modelPoints, "Points sampled on each model's surface")
		->check(CLI::Range(100, 1000000));
	app.add_option("--seed", o.seed, "Seed of the model sampling");
	app.add_flag("--quiet", o.quiet, "Do not report per-box failures");
	CLI11_PARSE(app, argc, argv);

	if (list) {
		for (const auto &n : availablePeers())
			std::printf("%s\n", n.c_str());
		return 0;
	}
	if (peerName.empty() || o.dataset.empty() || o.boxes.empty() || o.out.empty()) {
		std::fprintf(stderr, "ihf_peers: --peer, --dataset, --boxes and --out are required (see --help)\n");
		return 2;
	}
	auto peer = makePeer(peerName);
	if (!peer) {
		std::fprintf(stderr, "ihf_peers: unknown peer \"%s\"; built in:", peerName.c_str());
		for (const auto &n : availablePeers())
			std::fprintf(stderr, " %s", n.c_str());
		std::fprintf(stderr, "\n");
		return 2;
	}
	auto summary = ihf::peers::runPeer(*peer, o);
	if (!summary) {
		std::fprintf(stderr, "ihf_peers: %s\n", summary.error().message.c_str());
		return 1;
	}
	return 0;
}
