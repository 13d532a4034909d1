// SPDX-License-Identifier: MIT
// `ihf render`: one model at one pose to a BOP depth PNG, plus an optional
// false-colour preview.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "core/dataset/bop_io.h"
#include "core/geometry/mesh_import.h"
#include "core/render/depth_renderer.h"
#include "firmware_app/commands/command.h"

namespace ihf::app {

namespace {

struct RenderOptions {
	std::string model;
	std::string camera;
	std::vector<double> R;
	std::vector<double> t;
	std::string out;
	std::string preview;
	float nearMm = 1.0f;
};

// Jet-like ramp, red near and blue far; black where nothing was drawn.
void falseColour(const DepthImageMm &depth, std::vector<uint8_t> &rgb)
{
	float zMin = 0, zMax = 0;
	for (float z : depth.pixels()) {
		if (z <= 0)
			continue;
		zMin = zMin == 0 ? z : std::min(zMin, z);
		zMax = std::max(zMax, z);
	}
	const float range = std::max(zMax - zMin, 1e-3f);
	rgb.assign(depth.pixels().size() * 3, 0);
	for (size_t i = 0; i < depth.pixels().size(); ++i) {
		const float z = depth.pixels()[i];
		if (z <= 0)
			continue;
		const float s = 1.0f - (z - zMin) / range; // 1 = nearest
		auto ramp = [s](float centre) { return std::clamp(1.5f - std::abs(4.0f * s - centre), 0.0f, 1.0f); };
		rgb[3 * i + 0] = static_cast<uint8_t>(std::lround(255 * ramp(3)));
		rgb[3 * i + 1] = static_cast<uint8_t>(std::lround(255 * ramp(2)));
		rgb[3 * i + 2] = static_cast<uint8_t>(std::lround(255 * ramp(1)));
	}
}

int runRender(const RenderOptions &opt)
{
	Pose pose;
	for (int k = 0; k < 9; ++k)
		pose.R(k / 3, k % 3) = opt.R[k];
	pose.t = {opt.t[0], opt.t[1], opt.t[2]};
	const double orthoErr = (pose.R * pose.R.transpose() - Eigen::Matrix3d::Identity()).norm();
	if (!pose.R.allFinite() || !pose.t.allFinite() || orthoErr > 1e-3 || pose.R.determinant() < 0) {
		std::fprintf(stderr, "ihf render: --R is not a rotation matrix (row-major r11,...,r33)\n");
		return kExitUsage;
	}

	auto camera = readBopCamera(opt.camera);
	if (!camera) {
		std::fprintf(stderr, "ihf render: %s\n", camera.error().message.c_str());
		return kExitFailure;
	}
	const CameraIntrinsics &K = camera->intrinsics;
	if (!K.valid()) {
		std::fprintf(stderr, "ihf render: %s: intrinsics or image size invalid\n", opt.camera.c_str());
		return kExitFailure;
	}
	auto mesh = loadMesh(opt.model);
	if (!mesh) {
		std::fprintf(stderr, "ihf render: %s\n", mesh.error().message.c_str());
		return kExitFailure;
	}

	DepthRenderer renderer(mesh->vertices.size());
	renderer.setNearPlane(opt.nearMm);
	DepthImageMm depth(K.width, K.height);
	auto stats = renderer.render(*mesh, pose, K, depth.view());
	if (!stats) {
		std::fprintf(stderr, "ihf render: %s\n", stats.error().message.c_str());
		return kExitFailure;
	}

	// BOP depth PNG: raw * depth_scale = millimetres.
	DepthImage16 raw(K.width, K.height);
	int covered = 0, overflow = 0;
	float zMin = 0, zMax = 0;
	for (size_t i = 0; i < depth.pixels().size(); ++i) {
		const float z = depth.pixels()[i];
		if (z <= 0)
			continue;
		++covered;
		zMin = zMin == 0 ? z : std::min(zMin, z);
		zMax = std::max(zMax, z);
		const double value = std::round(z / camera->depthScale);
		if (value > 65535) {
			++overflow;
			continue;
		}
		raw.pixels()[i] = static_cast<uint16_t>(value);
	}
	if (covered == 0)
		std::fprintf(stderr, "ihf render: warning: the model is not visible at this pose\n");
	if (overflow)
		std::fprintf(stderr, "ihf render: warning: %d pixels beyond the 16-bit range left at 0\n", overflow);

	if (Status s = writeDepthPng(opt.out, raw); !s) {
		std::fprintf(stderr, "ihf render: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	if (!opt.preview.empty()) {
		std::vector<uint8_t> rgb;
		falseColour(depth, rgb);
		if (Status s = writePng8(opt.preview, K.width, K.height, 3, rgb.data()); !s) {
			std::fprintf(stderr, "ihf render: %s\n", s.error().message.c_str());
			return kExitFailure;
		}
	}
	std::printf("rendered %d pixels (%d triangles drawn), depth %.1f..%.1f mm -> %s\n", covered,
		    stats->trianglesDrawn, zMin, zMax, opt.out.c_str());
	return kExitOk;
}

} // namespace

void addRenderCommand(CLI::App &root, Action &action)
{
	auto opt = std::make_shared<RenderOptions>();
	auto *cmd = root.add_subcommand("render", "Render a model's depth at a pose to a 16-bit BOP depth PNG");
	cmd->add_option("--model", opt->model, std::string("Model mesh in mm (") + meshImportFormats() + ")")->required()->check(CLI::ExistingFile);
	cmd->add_option("--camera", opt->camera, "BOP camera.json (intrinsics, image size, depth_scale)")
		->required()
		->check(CLI::ExistingFile);
	cmd->add_option("--R", opt->R, "Rotation model-to-camera, row-major: r11,r12,...,r33")
		->required()
		->delimiter(',')
		->expected(9);
	cmd->add_option("--t", opt->t, "Translation model-to-camera in mm: tx,ty,tz")
		->required()
		->delimiter(',')
		->expected(3);
	cmd->add_option("--out", opt->out, "Output depth PNG, 16-bit, raw * depth_scale = mm, 0 = empty")
		->required();
	cmd->add_option("--preview", opt->preview, "Optional false-colour preview PNG (red near, blue far)");
	cmd->add_option("--near", opt->nearMm, "Near clipping plane in mm")
		->capture_default_str()
		->check(CLI::PositiveNumber);
	cmd->callback([&action, opt] { action = [opt] { return runRender(*opt); }; });
}

} // namespace ihf::app
