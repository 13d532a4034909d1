// SPDX-License-Identifier: MIT
#include "drivers/source_factory.h"

#ifdef IHF_HAVE_OPENNI2
#include "drivers/openni2_source.h"
#endif

namespace ihf {

const char *frameSourceUriHelp()
{
#ifdef IHF_HAVE_OPENNI2
	return "recording:PATH (an ihf .rec file), openni2: (first OpenNI2 device), "
	       "openni2:PATH.oni (an OpenNI2 recording), openni2:URI (an OpenNI2 device)";
#else
	return "recording:PATH (an ihf .rec file); openni2: is not in this build";
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
		return std::unique_ptr<FrameSource>(std::make_unique<RecordingSource>(rest, o, uri));
	}
	if (scheme == "openni2") {
#ifdef IHF_HAVE_OPENNI2
		OpenNi2SourceOptions o;
		o.realTime = options.pacing == Pacing::kRealTime;
		o.intrinsics = options.intrinsics;
		return std::unique_ptr<FrameSource>(std::make_unique<OpenNi2Source>(rest, o, uri));
#else
		return makeError(Errc::kUnsupported,
				 "frame source '" + uri +
					 "': this ihf was built without OpenNI2 (IHF_WITH_OPENNI2=OFF)");
#endif
	}
	return makeError(Errc::kInvalidArgument, "frame source '" + uri + "': unknown scheme '" +
							 scheme + "'; use " + frameSourceUriHelp());
}

} // namespace ihf
