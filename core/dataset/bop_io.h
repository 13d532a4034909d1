// SPDX-License-Identifier: MIT
#pragma once

// Readers and writers for the BOP files. Every error names the file and the
// JSON field (or CSV line/column) at fault. Writers go through a temporary
// file renamed into place, so a failed write never leaves a half file.

#include <filesystem>
#include <map>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/dataset/bop_types.h"

namespace ihf {

namespace fs = std::filesystem;

Expected<BopCamera> readBopCamera(const fs::path &file);
Status writeBopCamera(const fs::path &file, const BopCamera &camera);

Expected<std::map<int, ModelInfo>> readModelsInfo(const fs::path &file);
Status writeModelsInfo(const fs::path &file, const std::map<int, ModelInfo> &info);

Expected<std::map<int, SceneCamera>> readSceneCamera(const fs::path &file);
Status writeSceneCamera(const fs::path &file, const std::map<int, SceneCamera> &cams);

Expected<std::map<int, std::vector<GtInstance>>> readSceneGt(const fs::path &file);
Status writeSceneGt(const fs::path &file, const std::map<int, std::vector<GtInstance>> &gt);

Expected<std::map<int, std::vector<GtInfo>>> readSceneGtInfo(const fs::path &file);
Status writeSceneGtInfo(const fs::path &file, const std::map<int, std::vector<GtInfo>> &info);

Expected<std::vector<ResultRow>> readResultsCsv(const fs::path &file);
Status writeResultsCsv(const fs::path &file, const std::vector<ResultRow> &rows);

Expected<std::vector<Detection>> readDetections(const fs::path &file);
Status writeDetections(const fs::path &file, const std::vector<Detection> &dets);

// 16-bit single-channel PNG (BOP depth). A PNG of any other bit depth or
// channel count is an error naming the file.
Expected<DepthImage16> readDepthPng(const fs::path &file);
Status writeDepthPng(const fs::path &file, const DepthImage16 &image);

// 8-bit PNGs for pictures (visualisations, plots): channels 1 (grey) or 3 (RGB).
Status writePng8(const fs::path &file, int width, int height, int channels,
		 const uint8_t *pixels);

} // namespace ihf
