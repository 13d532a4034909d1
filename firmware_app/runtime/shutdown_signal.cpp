// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/shutdown_signal.h"

#include <pthread.h>
#include <sys/signalfd.h>
#include <unistd.h>

namespace ihf::app {

ShutdownSignal::ShutdownSignal()
{
	sigset_t set;
	sigemptyset(&set);
	sigaddset(&set, SIGINT);
	sigaddset(&set, SIGTERM);
	if (pthread_sigmask(SIG_BLOCK, &set, &previous_) != 0)
		return;
	fd_ = signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC);
	if (fd_ < 0)
		pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

ShutdownSignal::~ShutdownSignal()
{
	if (fd_ < 0)
		return;
	close(fd_);
	pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

bool ShutdownSignal::requested()
{
	if (signal_ || fd_ < 0)
		return signal_ != 0;
	signalfd_siginfo info;
	if (read(fd_, &info, sizeof(info)) == static_cast<ssize_t>(sizeof(info)))
		signal_ = static_cast<int>(info.ssi_signo);
	return signal_ != 0;
}

} // namespace ihf::app
