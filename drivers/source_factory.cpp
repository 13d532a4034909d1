// SPDX-License-Identifier: MIT
#include "drivers/source_factory.h"

#include "drivers/v4l2_source.h"
#ifdef IHF_HAVE_OPENNI2
#include "drivers/openni2_source.h"
#endif
#ifdef IHF_HAVE_LIBCAMERA
#include "drivers/libcamera_source.h"
#endif

namespace ihf {

const char *frameSourceUriHelp()
{
#ifdef IHF_HAVE_OPENNI2
	return "recording:PATH[?loop=1] (an ihf .rec file; loop=1 plays it again and again, indices and "
	       "time running on), openni2: (first OpenNI2 device), "
	       "openni2:PATH.oni (an OpenNI2 recording), openni2:URI (an OpenNI2 device), "
	       "v4l2:/dev/videoN[?format=z16|y16&width=W&height=H&fps=F&scale=MM&hfov=DEG&fx=..&fy=..&cx=..&cy=..] "
	       "(a V4L2 depth node), libcamera:[CAMERA-ID][?width=W&height=H&scale=MM&hfov=DEG] "
	       "(a raw depth/ToF stream; when built with libcamera)";
#else
	return "recording:PATH[?loop=1] (an ihf .rec file; loop=1 plays it again and again), v4l2:/dev/videoN[?...] (a V4L2 depth node), "
	       "libcamera:[CAMERA-ID] (when built with libcamera); openni2: is not in this build";
#endif
}

Expected<std::unique_ptr<FrameSource>> makeFrameSource(const std::string &uri,
						       const SourceOptions &options)
{
	const size_t colon = uri.find(':');
	if (colon == std::string::npos || colon == 0)
		return makeError(Errc::kInvalidArgument,
				 "frame source '" + uri + "': no scheme; use " + frameSourceUriHelp());
	const std::string scheme = uri.substr(0, colon);
	const std::string rest = uri.substr(colon + 1);

	if (scheme == "recording") {
		if (rest.empty())
			return makeError(Errc::kInvalidArgument,
					 "frame source '" + uri + "': recording: needs a file path");
		RecordingSourceOptions o;
		o.pacing = options.pacing;
		o.speed = options.speed;
		o.clock = options.clock;
		std::string path = rest;
		if (const size_t q = rest.rfind('?'); q != std::string::npos) {
			const std::string query = rest.substr(q + 1);
			if (query == "loop=1")
				o.loop = true;
			else if (query != "loop=0")
				return makeError(Errc::kInvalidArgument,
						 "frame source '" + uri + "': recording: takes only ?loop=0 or ?loop=1");
			path = rest.substr(0, q);
			if (path.empty())
				return makeError(Errc::kInvalidArgument,
						 "frame source '" + uri + "': recording: needs a file path");
		}
		return std::unique_ptr<FrameSource>(std::make_unique<RecordingSource>(path, o, uri));
	}
	if (scheme == "openni2") {
#ifdef IHF_HAVE_OPENNI2
		OpenNi2SourceOptions o;
		o.realTime = options.pacing == Pacing::kRealTime;
		o.speed = options.speed;
		o.clock = options.clock;
		o.intrinsics = options.intrinsics;
		return std::unique_ptr<FrameSource>(std::make_unique<OpenNi2Source>(rest, o, uri));
#else
		return makeError(Errc::kUnsupported,
				 "frame source '" + uri +
					 "': this ihf was built without OpenNI2 (IHF_WITH_OPENNI2=OFF)");
#endif
	}
	if (scheme == "v4l2") {
		Expected<V4l2Uri> parsed = parseV4l2Uri(rest);
		if (!parsed)
			return parsed.error();
		return std::unique_ptr<FrameSource>(
			std::make_unique<V4l2Source>(parsed->device, parsed->options, uri));
	}
	if (scheme == "libcamera") {
#ifdef IHF_HAVE_LIBCAMERA
		Expected<LibcameraUri> parsed = parseLibcameraUri(rest);
		if (!parsed)
			return parsed.error();
		return std::unique_ptr<FrameSource>(
			std::make_unique<LibcameraSource>(parsed->cameraId, parsed->options, uri));
#else
		return makeError(Errc::kUnsupported, "frame source '" + uri +
							     "': this ihf was built without libcamera (libcamera-dev missing)");
#endif
	}
	return makeError(Errc::kInvalidArgument, "frame source '" + uri + "': unknown scheme '" +
							 scheme + "'; use " + frameSourceUriHelp());
}

} // namespace ihf
