// SPDX-License-Identifier: MIT
#include "core/dataset/bop_frames.h"

#include <limits>
#include <string>

namespace ihf {

Expected<int> recordedSceneId(const BopDataset &dataset, int sceneId)
{
	if (sceneId >= 0)
		return sceneId;
	const std::vector<int> ids = dataset.sceneIds();
	if (ids.size() != 1) {
		std::string list;
		for (int id : ids)
			list += (list.empty() ? "" : ", ") + std::to_string(id);
		return makeError(Errc::kInvalidArgument,
				 dataset.root().string() + "/" + dataset.split() + " has " +
					 std::to_string(ids.size()) + " scenes (" + list +
					 "); choose one with --scene");
	}
	return ids.front();
}

std::vector<RecordedImage> recordedImages(const BopScene &scene)
{
	std::vector<RecordedImage> frames;
	frames.reserve(scene.cameras.size());
	for (const auto &[imId, cam] : scene.cameras)
		frames.push_back({static_cast<uint64_t>(imId), imId});
	return frames;
}

std::optional<int> recordedImageOf(const BopScene &scene, uint64_t frameIndex)
{
	if (frameIndex > static_cast<uint64_t>(std::numeric_limits<int>::max()))
		return std::nullopt;
	const int imId = static_cast<int>(frameIndex);
	if (!scene.cameras.count(imId))
		return std::nullopt;
	return imId;
}

} // namespace ihf
