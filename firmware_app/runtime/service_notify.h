// SPDX-License-Identifier: MIT
#pragma once

// systemd service notification for `ihf run` (Type=notify, WatchdogSec=):
// READY=1 once the loop runs, WATCHDOG=1 on every loop iteration (a frame,
// a timeout, a reopen wait), STOPPING=1 at the end. Through libsystemd's
// sd_notify when the build found it (IHF_HAVE_SYSTEMD); without it, or
// without NOTIFY_SOCKET in the environment (not started by systemd), every
// call does nothing. Never fails the run: a lost notification is systemd's
// to judge.

#include "firmware_app/runtime/run_loop.h"

namespace ihf::app {

class ServiceNotifier final : public LoopHeartbeat
{
public:
	ServiceNotifier();

	// Whether notifications go anywhere (built with libsystemd and
	// NOTIFY_SOCKET set).
	bool active() const { return active_; }
	// Built with libsystemd at all.
	static bool available();

	void beat() override; // READY=1 the first time, then WATCHDOG=1
	void stopping();

private:
	bool active_ = false;
	bool ready_ = false;
};

} // namespace ihf::app
