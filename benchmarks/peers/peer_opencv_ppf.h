// SPDX-License-Identifier: MIT
#pragma once

// OpenCV contrib surface_matching: PPF3DDetector (Drost et al. 2010, point
// pair features with Hough voting) followed by its own ICP.

#include <map>
#include <memory>

#include "benchmarks/peers/peer.h"

namespace ihf::peers {

struct OpenCvPpfParams {
	double samplingStep = 0.05;     // model sampling, relative to the model's extent (Drost's tau_d)
	double distanceStep = 0.05;     // feature distance quantisation, relative
	int numAngles = 30;             // feature angle quantisation
	double sceneSampleStep = 0.2;   // share of sampled scene points used as reference points
	double sceneDistance = 0.03;    // scene sampling, relative to the crop's extent
	int refineTop = 3;              // best-voted poses refined by ICP; lowest residual wins
	int icpIterations = 100;
	float icpTolerance = 0.005f;
	float icpRejectionScale = 2.5f;
	int icpLevels = 8;
};

class OpenCvPpfPeer : public Peer
{
public:
	explicit OpenCvPpfPeer(const OpenCvPpfParams &params);
	~OpenCvPpfPeer() override;
	const char *name() const override { return "opencv_ppf"; }
	Status prepare(const PeerModel &model) override;
	PeerEstimate estimate(int objId, std::span<const CloudPoint> scene) override;

private:
	struct Trained;
	OpenCvPpfParams params_;
	std::map<int, std::unique_ptr<Trained>> models_;
};

} // namespace ihf::peers
