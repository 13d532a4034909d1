// SPDX-License-Identifier: MIT
#include "benchmarks/peers/peer_opencv_ppf.h"

#include <algorithm>
#include <limits>

#include <opencv2/core.hpp>
#include <opencv2/surface_matching.hpp>

namespace ihf::peers {

struct OpenCvPpfPeer::Trained {
	std::unique_ptr<cv::ppf_match_3d::PPF3DDetector> detector;
	cv::Mat cloud; // Nx6 float: x y z nx ny nz, for ICP
};

OpenCvPpfPeer::OpenCvPpfPeer(const OpenCvPpfParams &params) : params_(params) {}

OpenCvPpfPeer::~OpenCvPpfPeer() = default;

Status OpenCvPpfPeer::prepare(const PeerModel &model)
{
	auto t = std::make_unique<Trained>();
	t->cloud = cv::Mat(static_cast<int>(model.points.size()), 6, CV_32F);
	for (size_t i = 0; i < model.points.size(); ++i) {
		float *r = t->cloud.ptr<float>(static_cast<int>(i));
		for (int k = 0; k < 3; ++k) {
			r[k] = model.points[i][k];
			r[3 + k] = model.normals[i][k];
		}
	}
	try {
		t->detector = std::make_unique<cv::ppf_match_3d::PPF3DDetector>(
			params_.samplingStep, params_.distanceStep, params_.numAngles);
		t->detector->trainModel(t->cloud);
	} catch (const cv::Exception &e) {
		return makeError(Errc::kInvalidArgument, std::string("PPF training: ") + e.what());
	}
	models_[model.objId] = std::move(t);
	return {};
}

PeerEstimate OpenCvPpfPeer::estimate(int objId, std::span<const CloudPoint> scene)
{
	PeerEstimate out;
	auto it = models_.find(objId);
	if (it == models_.end()) {
		out.reason = "no model";
		return out;
	}
	if (scene.size() < 10) {
		out.reason = "fewer than 10 points in the crop";
		return out;
	}
	cv::Mat pc(static_cast<int>(scene.size()), 6, CV_32F);
	for (size_t i = 0; i < scene.size(); ++i) {
		float *r = pc.ptr<float>(static_cast<int>(i));
		for (int k = 0; k < 3; ++k) {
			r[k] = scene[i].p[k];
			r[3 + k] = scene[i].n[k];
		}
	}
	try {
		std::vector<cv::ppf_match_3d::Pose3DPtr> results;
		it->second->detector->match(pc, results, params_.sceneSampleStep, params_.sceneDistance);
		if (results.empty()) {
			out.reason = "no PPF match";
			return out;
		}
		std::vector<cv::ppf_match_3d::Pose3DPtr> top(
			results.begin(), results.begin() + std::min<size_t>(results.size(), params_.refineTop));
		cv::ppf_match_3d::ICP icp(params_.icpIterations, params_.icpTolerance,
					  params_.icpRejectionScale, params_.icpLevels);
		icp.registerModelToScene(it->second->cloud, pc, top);
		const cv::ppf_match_3d::Pose3DPtr *best = nullptr;
		for (const auto &p : top)
			if (!best || p->residual < (*best)->residual)
				best = &p;
		const cv::Matx44d &m = (*best)->pose;
		for (int r = 0; r < 3; ++r) {
			for (int c = 0; c < 3; ++c)
				out.pose.R(r, c) = m(r, c);
			out.pose.t[r] = m(r, 3);
		}
		out.score = static_cast<double>((*best)->numVotes);
		out.found = true;
	} catch (const cv::Exception &e) {
		out.reason = std::string("OpenCV: ") + e.what();
	}
	return out;
}

} // namespace ihf::peers
