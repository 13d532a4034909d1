// SPDX-License-Identifier: MIT
#pragma once

// A BOP scene as the frames of a recording (`ihf record --from-bop`, `ihf
// synth --sequence`), and back: the scene is the one asked for or the
// split's only one; its images of scene_camera.json in image-id order are
// the frames, and a frame's index is its image id. `ihf eval --run-poses`
// maps the frames of `ihf run`'s pose lines back to images with the same
// rules.

#include <cstdint>
#include <optional>
#include <vector>

#include "core/common/expected.h"
#include "core/dataset/bop_dataset.h"

namespace ihf {

// `sceneId` when >= 0, else the split's only scene; with several scenes and
// none chosen, kInvalidArgument listing them.
Expected<int> recordedSceneId(const BopDataset &dataset, int sceneId);

struct RecordedImage {
	uint64_t frameIndex = 0;
	int imageId = 0;
};

// The recorded frames of a scene, in recording order.
std::vector<RecordedImage> recordedImages(const BopScene &scene);

// The image a frame index was recorded from; nullopt if none was.
std::optional<int> recordedImageOf(const BopScene &scene, uint64_t frameIndex);

} // namespace ihf
