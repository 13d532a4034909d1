// SPDX-License-Identifier: MIT
#pragma once

// The run loop's view of a USB depth sensor: a UsbSensorWatch polled when
// the enumerator says the bus changed (libusb hotplug) or at each check
// (periodic enumeration). Unplugs and returns are reported on the log.

#include "drivers/usb_watch.h"
#include "firmware_app/runtime/run_loop.h"

namespace ihf::app {

class UsbSensorPresence : public SourcePresence
{
public:
	UsbSensorPresence(UsbEnumerator &enumerator, UsbSensorFilter filter);

	void update(std::FILE *log) override;
	bool present() const override { return !watch_.present().empty(); }

private:
	UsbSensorWatch watch_;
	bool first_ = true;
	bool failed_ = false;
};

} // namespace ihf::app
