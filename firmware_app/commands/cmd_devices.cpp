// SPDX-License-Identifier: MIT
// `ihf devices`: the depth sensors this machine has, by every route ihf
// reads them: known USB sensors (libusb, by vendor/product id), V4L2 capture
// nodes and their depth formats, OpenNI2 devices, libcamera cameras. With
// --watch SECONDS it then reports USB sensors plugged in and unplugged.

#include <chrono>
#include <cstdio>

#ifdef IHF_HAVE_OPENNI2
#include "drivers/openni2_source.h"
#endif
#include "drivers/usb_watch.h"
#include "drivers/v4l2_source.h"
#ifdef IHF_HAVE_LIBCAMERA
#include "drivers/libcamera_source.h"
#endif
#include "firmware_app/commands/command.h"
#include "firmware_app/runtime/shutdown_signal.h"

namespace ihf::app {

namespace {

int runDevices(double watchSeconds)
{
	ShutdownSignal shutdown; // --watch ends cleanly on SIGINT
	int found = 0;

	std::unique_ptr<LibusbEnumerator> usb;
	if (Expected<std::unique_ptr<LibusbEnumerator>> e = LibusbEnumerator::create(); e) {
		usb = std::move(e.value());
		Expected<std::vector<UsbSensor>> sensors = findUsbSensors(*usb);
		if (!sensors) {
			std::printf("usb        (%s)\n", sensors.error().message.c_str());
		} else {
			for (const UsbSensor &s : *sensors) {
				std::printf("usb        %s  %s  (read with %s)\n", s.describe().c_str(), s.model->model,
					    s.model->sourceHint);
				++found;
			}
			if (sensors->empty())
				std::printf("usb        no known depth sensor (hotplug: %s)\n",
					    usb->hotplug() ? "libusb events" : "periodic enumeration");
		}
	} else {
		std::printf("usb        (%s)\n", e.error().message.c_str());
	}

	const std::vector<V4l2NodeInfo> nodes = listV4l2Nodes();
	for (const V4l2NodeInfo &n : nodes) {
		const bool depth = n.z16 || n.y16;
		std::printf("v4l2       %s  %s (%s, %s)  formats %s%s\n", n.path.c_str(), n.card.c_str(),
			    n.driver.c_str(), n.busInfo.c_str(), n.formats.c_str(),
			    depth ? "" : "  (no Z16/Y16 depth)");
		if (depth) {
			std::printf("           uri v4l2:%s?format=%s\n", n.path.c_str(), n.z16 ? "z16" : "y16");
			++found;
		}
	}
	if (nodes.empty())
		std::printf("v4l2       no capture node in /dev/video*\n");

#ifdef IHF_HAVE_OPENNI2
	if (Expected<std::vector<std::string>> oni = listOpenNi2Devices(); oni) {
		for (const std::string &d : *oni) {
			std::printf("openni2    %s\n", d.c_str());
			++found;
		}
		if (oni->empty())
			std::printf("openni2    no device\n");
	} else {
		std::printf("openni2    (%s)\n", oni.error().message.c_str());
	}
#else
	std::printf("openni2    (not built in)\n");
#endif

#ifdef IHF_HAVE_LIBCAMERA
	if (Expected<std::vector<std::string>> cams = listLibcameraCameras(); cams) {
		for (const std::string &id : *cams) {
			std::printf("libcamera  %s  -> libcamera:%s\n", id.c_str(), id.c_str());
			++found;
		}
		if (cams->empty())
			std::printf("libcamera  no camera\n");
	} else {
		std::printf("libcamera  (%s)\n", cams.error().message.c_str());
	}
#else
	std::printf("libcamera  (not built in)\n");
#endif
	std::printf("%d depth source%s found\n", found, found == 1 ? "" : "s");
	std::fflush(stdout);

	if (watchSeconds > 0 && usb) {
		UsbSensorWatch watch(*usb);
		(void)watch.poll(); // the current set
		const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(watchSeconds);
		std::printf("watching USB for %.0f s (%s)\n", watchSeconds,
			    usb->hotplug() ? "libusb hotplug events" : "enumerating every second");
		std::fflush(stdout);
		while (std::chrono::steady_clock::now() < end && !shutdown.requested()) {
			if (!usb->waitForChange(std::chrono::milliseconds(usb->hotplug() ? 200 : 1000)))
				continue;
			Expected<std::vector<UsbSensorEvent>> events = watch.poll();
			if (!events) {
				std::fprintf(stderr, "ihf devices: %s\n", events.error().message.c_str());
				return kExitFailure;
			}
			for (const UsbSensorEvent &ev : *events)
				std::printf("%s  %s  %s\n", ev.arrived ? "plugged in" : "unplugged ",
					    ev.sensor.describe().c_str(), ev.sensor.model->model);
			std::fflush(stdout);
		}
	}
	return kExitOk;
}

} // namespace

void addDevicesCommand(CLI::App &root, Action &action)
{
	auto watch = std::make_shared<double>(0);
	auto *cmd = root.add_subcommand("devices", "List depth sensors: USB (known ids), V4L2, OpenNI2, libcamera");
	cmd->add_option("--watch", *watch, "then report USB sensors plugged in / unplugged for SECONDS")
		->check(CLI::NonNegativeNumber);
	cmd->callback([watch, &action] { action = [watch] { return runDevices(*watch); }; });
}

} // namespace ihf::app
