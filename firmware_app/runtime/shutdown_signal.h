// SPDX-License-Identifier: MIT
#pragma once

// SIGINT and SIGTERM as a file descriptor (signalfd): the constructor blocks
// both signals in the calling thread (create it before any other thread, so
// every thread inherits the mask) and the destructor restores the mask. The
// loop polls requested() between frames and waits on fd() alongside its
// inputs, so a signal ends the run cleanly at a frame boundary. No handler,
// no global flag.

#include <csignal>

namespace ihf::app {

class ShutdownSignal
{
public:
	ShutdownSignal();
	~ShutdownSignal();
	ShutdownSignal(const ShutdownSignal &) = delete;
	ShutdownSignal &operator=(const ShutdownSignal &) = delete;

	// False if signalfd() failed (the signals then keep their default action).
	bool valid() const { return fd_ >= 0; }
	int fd() const { return fd_; }
	// True once SIGINT or SIGTERM arrived (latched); never blocks.
	bool requested();
	// The signal that arrived (0 if none).
	int signal() const { return signal_; }

private:
	int fd_ = -1;
	int signal_ = 0;
	sigset_t previous_;
};

} // namespace ihf::app
