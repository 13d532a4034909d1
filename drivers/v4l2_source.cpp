// SPDX-License-Identifier: MIT
#include "drivers/v4l2_source.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include "drivers/clock.h"

namespace ihf {

namespace {

// ioctl with EINTR retried.
int xioctl(int fd, unsigned long request, void *arg)
{
	int r;
	do
		r = ioctl(fd, request, arg);
	while (r < 0 && errno == EINTR);
	return r;
}

std::string fourccText(uint32_t f)
{
	std::string s(4, ' ');
	for (int i = 0; i < 4; ++i) {
		const char c = static_cast<char>((f >> (8 * i)) & 0xff);
		s[i] = c >= 32 && c < 127 ? c : '?';
	}
	return s;
}

bool isRemoval(int err) { return err == ENODEV || err == ENXIO; }

template<typename T>
bool parseNumber(std::string_view s, T &out)
{
	if constexpr (std::is_floating_point_v<T>) {
		// from_chars for double is in libstdc++ 11+.
		auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
		return ec == std::errc() && p == s.data() + s.size() && std::isfinite(out);
	} else {
		auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
		return ec == std::errc() && p == s.data() + s.size();
	}
}

} // namespace

Expected<V4l2Uri> parseV4l2Uri(const std::string &rest)
{
	V4l2Uri u;
	const size_t q = rest.find('?');
	u.device = rest.substr(0, q);
	const std::string uri = "v4l2:" + rest;
	if (u.device.empty())
		return makeError(Errc::kInvalidArgument, uri + ": needs a device node, e.g. v4l2:/dev/video0");
	if (q == std::string::npos)
		return u;
	V4l2SourceOptions &o = u.options;
	double fx = 0, fy = 0, cx = -1, cy = -1;
	int given = 0;
	std::string_view query(rest);
	query.remove_prefix(q + 1);
	while (!query.empty()) {
		const size_t amp = query.find('&');
		std::string_view item = query.substr(0, amp);
		query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
		const size_t eq = item.find('=');
		const std::string key(item.substr(0, eq));
		const std::string_view value = eq == std::string_view::npos ? std::string_view() : item.substr(eq + 1);
		bool ok = eq != std::string_view::npos;
		if (!ok) {
		} else if (key == "format") {
			if (value == "z16")
				o.format = V4l2DepthFormat::kZ16;
			else if (value == "y16")
				o.format = V4l2DepthFormat::kY16;
			else if (value == "auto")
				o.format = V4l2DepthFormat::kAuto;
			else
				ok = false;
		} else if (key == "width") {
			ok = parseNumber(value, o.width) && o.width > 0;
		} else if (key == "height") {
			ok = parseNumber(value, o.height) && o.height > 0;
		} else if (key == "fps") {
			ok = parseNumber(value, o.fps) && o.fps > 0;
		} else if (key == "buffers") {
			ok = parseNumber(value, o.buffers) && o.buffers >= 2 && o.buffers <= 32;
		} else if (key == "scale") {
			ok = parseNumber(value, o.scale) && o.scale > 0;
		} else if (key == "hfov") {
			ok = parseNumber(value, o.hfovDeg) && o.hfovDeg > 0 && o.hfovDeg < 180;
		} else if (key == "fx") {
			ok = parseNumber(value, fx) && fx > 0, ++given;
		} else if (key == "fy") {
			ok = parseNumber(value, fy) && fy > 0, ++given;
		} else if (key == "cx") {
			ok = parseNumber(value, cx), ++given;
		} else if (key == "cy") {
			ok = parseNumber(value, cy), ++given;
		} else {
			return makeError(Errc::kInvalidArgument,
					 uri + ": unknown key '" + key +
						 "' (format, width, height, fps, buffers, scale, hfov, fx, fy, cx, cy)");
		}
		if (!ok)
			return makeError(Errc::kInvalidArgument, uri + ": bad value for '" + key + "'");
	}
	if (given != 0 && given != 4)
		return makeError(Errc::kInvalidArgument, uri + ": give all of fx, fy, cx, cy or none");
	if (given == 4) {
		CameraIntrinsics k;
		k.fx = fx, k.fy = fy, k.cx = cx, k.cy = cy;
		o.intrinsics = k; // width/height filled at open()
	}
	return u;
}

std::vector<V4l2NodeInfo> listV4l2Nodes()
{
	std::vector<V4l2NodeInfo> nodes;
	for (int i = 0; i < 64; ++i) {
		const std::string path = "/dev/video" + std::to_string(i);
		const int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
		if (fd < 0)
			continue;
		v4l2_capability cap{};
		if (xioctl(fd, VIDIOC_QUERYCAP, &cap) == 0) {
			const uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
			if (caps & V4L2_CAP_VIDEO_CAPTURE) {
				V4l2NodeInfo n;
				n.path = path;
				n.card = reinterpret_cast<const char *>(cap.card);
				n.driver = reinterpret_cast<const char *>(cap.driver);
				n.busInfo = reinterpret_cast<const char *>(cap.bus_info);
				for (uint32_t k = 0;; ++k) {
					v4l2_fmtdesc d{};
					d.index = k;
					d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
					if (xioctl(fd, VIDIOC_ENUM_FMT, &d) < 0)
						break;
					n.z16 |= d.pixelformat == V4L2_PIX_FMT_Z16;
					n.y16 |= d.pixelformat == V4L2_PIX_FMT_Y16;
					if (!n.formats.empty())
						n.formats += ',';
					n.formats += fourccText(d.pixelformat);
				}
				nodes.push_back(std::move(n));
			}
		}
		::close(fd);
	}
	return nodes;
}

V4l2Source::V4l2Source(std::string device, V4l2SourceOptions options, std::string uri)
	: device_(std::move(device)), options_(std::move(options))
{
	info_.uri = uri.empty() ? "v4l2:" + device_ : std::move(uri);
	info_.live = true;
}

V4l2Source::~V4l2Source()
{
	stop();
	closeDevice();
}

Error V4l2Source::deviceError(const char *what, int err) const
{
	if (isRemoval(err))
		return makeError(Errc::kIo, info_.uri + ": device " + device_ + " was removed (" + what +
						    ": " + std::strerror(err) + "); reopen when it is back");
	return makeError(Errc::kIo, info_.uri + ": " + what + " failed on " + device_ + ": " +
					    std::strerror(err));
}

void V4l2Source::closeDevice()
{
	if (fd_ >= 0)
		::close(fd_);
	fd_ = -1;
}

void V4l2Source::releaseBuffers()
{
	for (Buffer &b : buffers_)
		if (b.start)
			munmap(b.start, b.length);
	buffers_.clear();
	if (fd_ >= 0 && !removed_) {
		v4l2_requestbuffers req{};
		req.count = 0;
		req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		req.memory = V4L2_MEMORY_MMAP;
		xioctl(fd_, VIDIOC_REQBUFS, &req);
	}
}

Status V4l2Source::open()
{
	stop();
	closeDevice();
	removed_ = false;
	counters_ = {};
	lastIndex_.reset();

	fd_ = ::open(device_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
	if (fd_ < 0) {
		const int err = errno;
		if (err == ENOENT || isRemoval(err))
			return makeError(Errc::kNotFound, info_.uri + ": no device " + device_ + " (" +
								  std::strerror(err) + "; unplugged?)");
		return makeError(Errc::kIo, info_.uri + ": cannot open " + device_ + ": " + std::strerror(err));
	}
	auto fail = [this](Error e) -> Status {
		closeDevice();
		return e;
	};

	v4l2_capability cap{};
	if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0)
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ +
								  " is not a V4L2 device (VIDIOC_QUERYCAP: " +
								  std::strerror(errno) + ")"));
	const uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
	if (!(caps & V4L2_CAP_VIDEO_CAPTURE))
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ +
								  " is not a single-planar video capture node"));
	if (!(caps & V4L2_CAP_STREAMING))
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ + " cannot stream (no mmap I/O)"));

	// The depth formats the device offers.
	bool hasZ16 = false, hasY16 = false;
	std::string offered;
	for (uint32_t i = 0;; ++i) {
		v4l2_fmtdesc d{};
		d.index = i;
		d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		if (xioctl(fd_, VIDIOC_ENUM_FMT, &d) < 0)
			break;
		hasZ16 |= d.pixelformat == V4L2_PIX_FMT_Z16;
		hasY16 |= d.pixelformat == V4L2_PIX_FMT_Y16;
		offered += (offered.empty() ? "" : ", ") + fourccText(d.pixelformat);
	}
	uint32_t want = 0;
	switch (options_.format) {
	case V4l2DepthFormat::kAuto:
		want = hasZ16 ? V4L2_PIX_FMT_Z16 : hasY16 ? V4L2_PIX_FMT_Y16 : 0;
		break;
	case V4l2DepthFormat::kZ16:
		want = hasZ16 ? V4L2_PIX_FMT_Z16 : 0;
		break;
	case V4l2DepthFormat::kY16:
		want = hasY16 ? V4L2_PIX_FMT_Y16 : 0;
		break;
	}
	if (!want)
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ + " offers no " +
								  (options_.format == V4l2DepthFormat::kZ16 ? "Z16"
								   : options_.format == V4l2DepthFormat::kY16 ? "Y16"
													      : "Z16 or Y16") +
								  " depth format (offers: " + offered + ")"));

	v4l2_format fmt{};
	fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	if (xioctl(fd_, VIDIOC_G_FMT, &fmt) < 0)
		return fail(deviceError("VIDIOC_G_FMT", errno));
	fmt.fmt.pix.pixelformat = want;
	if (options_.width)
		fmt.fmt.pix.width = options_.width;
	if (options_.height)
		fmt.fmt.pix.height = options_.height;
	fmt.fmt.pix.field = V4L2_FIELD_NONE;
	fmt.fmt.pix.bytesperline = 0; // the driver's choice
	if (xioctl(fd_, VIDIOC_S_FMT, &fmt) < 0)
		return fail(deviceError("VIDIOC_S_FMT", errno));
	const v4l2_pix_format &pix = fmt.fmt.pix;
	if (pix.pixelformat != want)
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ + " refused " +
								  fourccText(want) + " (gave " + fourccText(pix.pixelformat) + ")"));
	if ((options_.width && static_cast<int>(pix.width) != options_.width) ||
	    (options_.height && static_cast<int>(pix.height) != options_.height))
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ + " cannot capture " +
								  std::to_string(options_.width) + "x" +
								  std::to_string(options_.height) + " (nearest " +
								  std::to_string(pix.width) + "x" +
								  std::to_string(pix.height) + ")"));
	if (pix.width == 0 || pix.height == 0 || pix.bytesperline < pix.width * 2 || pix.bytesperline % 2)
		return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ +
								  " reports an unusable frame layout"));
	pixelFormat_ = want;
	fourcc_ = fourccText(want);
	bytesPerLine_ = static_cast<int>(pix.bytesperline);
	frameBytes_ = static_cast<size_t>(pix.bytesperline) * (pix.height - 1) + pix.width * 2;

	if (options_.fps > 0) {
		v4l2_streamparm parm{};
		parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		if (xioctl(fd_, VIDIOC_G_PARM, &parm) < 0 ||
		    !(parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME))
			return fail(makeError(Errc::kUnsupported, info_.uri + ": " + device_ +
									  " cannot set a frame rate"));
		parm.parm.capture.timeperframe.numerator = 1;
		parm.parm.capture.timeperframe.denominator = options_.fps;
		if (xioctl(fd_, VIDIOC_S_PARM, &parm) < 0)
			return fail(deviceError("VIDIOC_S_PARM", errno));
	}

	const int w = static_cast<int>(pix.width), h = static_cast<int>(pix.height);
	if (options_.intrinsics) {
		info_.intrinsics = *options_.intrinsics;
	} else {
		const double f = w / (2.0 * std::tan(options_.hfovDeg * M_PI / 360.0));
		info_.intrinsics.fx = f;
		info_.intrinsics.fy = f;
		info_.intrinsics.cx = (w - 1) / 2.0;
		info_.intrinsics.cy = (h - 1) / 2.0;
	}
	info_.intrinsics.width = w;
	info_.intrinsics.height = h;
	info_.depthScale = options_.scale;
	info_.sensorId = std::string("V4L2 ") + reinterpret_cast<const char *>(cap.card) + " (" +
			 reinterpret_cast<const char *>(cap.driver) + ", " +
			 reinterpret_cast<const char *>(cap.bus_info) + ", " + device_ + ", " + fourcc_ + ")";
	return {};
}

Status V4l2Source::start()
{
	if (fd_ < 0)
		return makeError(Errc::kInvalidArgument, info_.uri + ": start() before open()");
	stop();

	v4l2_requestbuffers req{};
	req.count = static_cast<uint32_t>(options_.buffers);
	req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	req.memory = V4L2_MEMORY_MMAP;
	if (xioctl(fd_, VIDIOC_REQBUFS, &req) < 0)
		return deviceError("VIDIOC_REQBUFS", errno);
	if (req.count < 2) {
		releaseBuffers();
		return makeError(Errc::kUnsupported, info_.uri + ": " + device_ + " gave " +
							     std::to_string(req.count) + " buffers, need 2");
	}
	buffers_.resize(req.count);
	for (uint32_t i = 0; i < req.count; ++i) {
		v4l2_buffer b{};
		b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		b.memory = V4L2_MEMORY_MMAP;
		b.index = i;
		if (xioctl(fd_, VIDIOC_QUERYBUF, &b) < 0) {
			Error e = deviceError("VIDIOC_QUERYBUF", errno);
			releaseBuffers();
			return e;
		}
		void *p = mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, b.m.offset);
		if (p == MAP_FAILED) {
			Error e = deviceError("mmap", errno);
			releaseBuffers();
			return e;
		}
		buffers_[i] = {p, b.length};
		if (b.length < frameBytes_) {
			releaseBuffers();
			return makeError(Errc::kUnsupported, info_.uri + ": buffers smaller than a frame");
		}
		if (xioctl(fd_, VIDIOC_QBUF, &b) < 0) {
			Error e = deviceError("VIDIOC_QBUF", errno);
			releaseBuffers();
			return e;
		}
	}
	v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0) {
		Error e = deviceError("VIDIOC_STREAMON", errno);
		releaseBuffers();
		return e;
	}
	streaming_ = true;
	held_ = -1;
	return {};
}

void V4l2Source::stop()
{
	if (fd_ < 0)
		return;
	if (streaming_ && !removed_) {
		v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		xioctl(fd_, VIDIOC_STREAMOFF, &type);
	}
	streaming_ = false;
	held_ = -1;
	releaseBuffers();
}

Status V4l2Source::requeueHeld()
{
	if (held_ < 0)
		return {};
	v4l2_buffer b{};
	b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	b.memory = V4L2_MEMORY_MMAP;
	b.index = static_cast<uint32_t>(held_);
	held_ = -1;
	if (xioctl(fd_, VIDIOC_QBUF, &b) < 0) {
		removed_ = isRemoval(errno);
		return deviceError("VIDIOC_QBUF", errno);
	}
	return {};
}

Expected<FrameOutcome> V4l2Source::next(Frame &frame, std::chrono::nanoseconds timeout)
{
	if (!streaming_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": next() before start()");
	if (Status s = requeueHeld(); !s)
		return s.error();

	SteadyPacingClock clock;
	const int64_t deadline = clock.nowNs() + timeout.count();
	for (;;) {
		const int64_t left = deadline - clock.nowNs();
		pollfd p{fd_, POLLIN, 0};
		const int ms = left <= 0 ? 0 : static_cast<int>((left + 999999) / 1000000);
		const int r = poll(&p, 1, ms);
		if (r < 0) {
			if (errno == EINTR) {
				++eintr_;
				continue; // a signal, not a timeout: wait for what is left
			}
			return deviceError("poll", errno);
		}
		if (r == 0) {
			++counters_.timeouts;
			return FrameOutcome::kTimeout;
		}

		v4l2_buffer b{};
		b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		b.memory = V4L2_MEMORY_MMAP;
		if (xioctl(fd_, VIDIOC_DQBUF, &b) < 0) {
			const int err = errno;
			if (err == EAGAIN && !(p.revents & (POLLERR | POLLHUP | POLLNVAL)))
				continue;
			removed_ = isRemoval(err) || (p.revents & (POLLHUP | POLLNVAL));
			if (removed_)
				return deviceError("VIDIOC_DQBUF", isRemoval(err) ? err : ENODEV);
			return deviceError(p.revents & POLLERR ? "poll reported an error; VIDIOC_DQBUF"
							       : "VIDIOC_DQBUF",
					   err);
		}
		const bool incomplete = b.bytesused != 0 && b.bytesused < frameBytes_;
		if ((b.flags & V4L2_BUF_FLAG_ERROR) || incomplete || b.index >= buffers_.size()) {
			// Queue it back and wait for the next one. Its sequence number
			// is taken, so it does not count as a gap (dropped) as well.
			++counters_.corrupt;
			if (b.index < buffers_.size())
				lastIndex_ = b.sequence;
			if (b.index < buffers_.size()) {
				held_ = static_cast<int>(b.index);
				if (Status s = requeueHeld(); !s)
					return s.error();
			}
			continue;
		}

		const int64_t stampNs = static_cast<int64_t>(b.timestamp.tv_sec) * 1000000000 +
					static_cast<int64_t>(b.timestamp.tv_usec) * 1000;
		const bool monotonic = (b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
		frame.index = b.sequence;
		frame.deviceTimestampNs = stampNs;
		// The buffer's stamp when it is on the steady clock; never later than
		// now (vivid stamps a nominal end of frame that can lie ahead).
		const int64_t now = clock.nowNs();
		frame.hostTimestampNs = monotonic && stampNs > 0 ? std::min(stampNs, now) : now;
		frame.intrinsics = info_.intrinsics;
		frame.depthScale = info_.depthScale;
		frame.depth = ImageView<const uint16_t>(static_cast<const uint16_t *>(buffers_[b.index].start),
							info_.intrinsics.width, info_.intrinsics.height,
							bytesPerLine_ / 2);
		held_ = static_cast<int>(b.index);
		if (lastIndex_ && frame.index > *lastIndex_ + 1)
			counters_.dropped += frame.index - *lastIndex_ - 1;
		lastIndex_ = frame.index;
		++counters_.delivered;
		return FrameOutcome::kFrame;
	}
}

} // namespace ihf
