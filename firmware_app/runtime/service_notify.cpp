// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/service_notify.h"

#include <cstdlib>

#ifdef IHF_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

namespace ihf::app {

ServiceNotifier::ServiceNotifier()
{
#ifdef IHF_HAVE_SYSTEMD
	// sd_notify reads NOTIFY_SOCKET itself on every call (and leaves it
	// set); here it only decides whether beats are worth a call at all.
	active_ = std::getenv("NOTIFY_SOCKET") != nullptr;
#endif
}

bool ServiceNotifier::available()
{
#ifdef IHF_HAVE_SYSTEMD
	return true;
#else
	return false;
#endif
}

void ServiceNotifier::beat()
{
	if (!active_)
		return;
#ifdef IHF_HAVE_SYSTEMD
	// One datagram per iteration; a negative return (socket gone) is
	// ignored, as systemd then restarts the service by its own rules.
	if (!ready_) {
		ready_ = true;
		sd_notify(0, "READY=1\nWATCHDOG=1");
	} else {
		sd_notify(0, "WATCHDOG=1");
	}
#endif
}

void ServiceNotifier::stopping()
{
	if (!active_)
		return;
#ifdef IHF_HAVE_SYSTEMD
	sd_notify(0, "STOPPING=1");
#endif
}

} // namespace ihf::app
