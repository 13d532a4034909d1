// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/usb_presence.h"

namespace ihf::app {

UsbSensorPresence::UsbSensorPresence(UsbEnumerator &enumerator, UsbSensorFilter filter)
	: watch_(enumerator, filter)
{
}

void UsbSensorPresence::update(std::FILE *log)
{
	if (!first_ && !watch_.enumerator().waitForChange(std::chrono::milliseconds(0)))
		return;
	Expected<std::vector<UsbSensorEvent>> events = watch_.poll();
	if (!events) {
		if (!failed_)
			std::fprintf(log, "ihf run: USB watch: %s\n", events.error().message.c_str());
		failed_ = true;
		return;
	}
	failed_ = false;
	for (const UsbSensorEvent &e : *events)
		std::fprintf(log, "ihf run: USB sensor %s: %s (%s)\n",
			     first_ ? "present" : e.arrived ? "plugged in" : "unplugged",
			     e.sensor.model->model, e.sensor.describe().c_str());
	if (first_ && watch_.present().empty())
		std::fprintf(log, "ihf run: USB watch: no known depth sensor plugged in\n");
	first_ = false;
}

} // namespace ihf::app
