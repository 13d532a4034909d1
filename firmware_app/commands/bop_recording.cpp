// SPDX-License-Identifier: MIT
#include "firmware_app/commands/bop_recording.h"

#include <charconv>
#include <cmath>
#include <map>
#include <vector>

#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_frames.h"
#include "core/dataset/bop_io.h"
#include "drivers/recording_writer.h"

namespace ihf {

namespace {

// The detections of one scene as `ihf run` box lines, one per recorded
// image, numbers exact.
Status writeBoxLines(const std::filesystem::path &out, const std::vector<Detection> &dets,
		     const BopScene &scene)
{
	auto num = [](std::string &s, double v) {
		char buf[32];
		auto [p, ec] = std::to_chars(buf, buf + sizeof(buf), v);
		s.append(buf, ec == std::errc() ? p : buf);
	};
	std::string text;
	for (const RecordedImage &image : recordedImages(scene)) {
		text += "{\"frame\":" + std::to_string(image.frameIndex) + ",\"boxes\":[";
		bool first = true;
		for (const Detection &d : dets) {
			if (d.sceneId != scene.sceneId || d.imageId != image.imageId)
				continue;
			text += first ? "" : ",";
			first = false;
			text += "{\"obj_id\":" + std::to_string(d.categoryId) + ",\"bbox\":[";
			for (int k = 0; k < 4; ++k) {
				if (k)
					text += ",";
				num(text, d.bbox[k]);
			}
			text += "]}";
		}
		text += "]}\n";
	}
	return writeFileAtomic(out, text);
}

bool sameCamera(const SceneCamera &a, const SceneCamera &b)
{
	const CameraIntrinsics &p = a.intrinsics, &q = b.intrinsics;
	return p.fx == q.fx && p.fy == q.fy && p.cx == q.cx && p.cy == q.cy &&
	       a.depthScale == b.depthScale;
}

} // namespace

Expected<BopRecordingResult> recordBopScene(const BopRecordingRequest &r)
{
	Expected<BopDataset> ds = BopDataset::open(r.dataset, r.split);
	if (!ds)
		return ds.error();
	Expected<int> chosen = recordedSceneId(*ds, r.sceneId);
	if (!chosen)
		return chosen.error();
	const int sceneId = *chosen;
	Expected<BopScene> scene = ds->loadScene(sceneId);
	if (!scene)
		return scene.error();
	if (scene->cameras.empty())
		return makeError(Errc::kNotFound,
				 ds->sceneDir(sceneId).string() + ": scene_camera.json lists no images");

	const auto &[firstId, firstCam] = *scene->cameras.begin();
	for (const auto &[imId, cam] : scene->cameras) {
		if (!sameCamera(cam, firstCam))
			return makeError(Errc::kUnsupported,
					 (ds->sceneDir(sceneId) / "scene_camera.json").string() + ": image " +
						 std::to_string(imId) +
						 " has a different cam_K or depth_scale than image " +
						 std::to_string(firstId) +
						 "; a recording has one camera (split the scene)");
	}

	recording::RecordingHeader header;
	header.sensorId = !r.sensorId.empty()
				  ? r.sensorId
				  : "bop:" + r.dataset.filename().string() + "/" + ds->split() + "/" +
					    std::to_string(sceneId);
	header.intrinsics = firstCam.intrinsics;
	header.depthScale = firstCam.depthScale;
	RecordingWriterOptions wo;
	wo.compress = r.compress;
	Expected<RecordingWriter> writer = RecordingWriter::create(r.out, header, wo);
	if (!writer)
		return writer.error();

	int64_t n = 0;
	for (const RecordedImage &image : recordedImages(*scene)) {
		const std::filesystem::path png = ds->depthPath(sceneId, image.imageId);
		Expected<DepthImage16> depth = readDepthPng(png);
		if (!depth)
			return depth.error();
		if (depth->width() != header.intrinsics.width || depth->height() != header.intrinsics.height)
			return makeError(Errc::kCorrupt,
					 png.string() + ": image is " + std::to_string(depth->width()) + "x" +
						 std::to_string(depth->height()) + ", camera.json says " +
						 std::to_string(header.intrinsics.width) + "x" +
						 std::to_string(header.intrinsics.height));
		const int64_t t = std::llround(static_cast<double>(n) * 1e9 / r.fps);
		FrameStamp stamp{image.frameIndex, t, t};
		if (Status s = writer->append(stamp, depth->view()); !s)
			return s.error();
		++n;
	}
	if (Status s = writer->finish(); !s)
		return s.error();
	if (!r.boxesOut.empty()) {
		Expected<std::vector<Detection>> dets = readDetections(r.boxes);
		if (!dets)
			return dets.error();
		if (Status st = writeBoxLines(r.boxesOut, *dets, *scene); !st)
			return st.error();
	}
	return BopRecordingResult{sceneId, n};
}

} // namespace ihf
