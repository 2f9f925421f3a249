// SPDX-License-Identifier: GPL-2.0-or-later
// SIGINT, SIGTERM and SIGHUP remove the temporary files and folders in
// flight before the program ends, so that an interrupted write leaves no
// `.tmp` behind. The signals are blocked in every thread and taken by one
// thread that waits for them (sigwait): the cleanup then runs as ordinary
// code, not in a signal handler, where almost nothing is safe to call.
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <system_error>
#include <thread>

#include "commands.h"
#include "handeye/io/atomic_file.h"

namespace handeye::tools {
namespace {

std::atomic<bool> interrupted{false};

}  // namespace

void EndIfInterrupted() {
  while (interrupted) pause();  // the thread that took the signal ends the program
}

void RemoveTemporariesOnInterrupt() {
  sigset_t signals;
  sigemptyset(&signals);
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    // A signal the program was started to ignore (nohup, `cmd &` in a script)
    // stays ignored.
    struct sigaction current;
    if (sigaction(signal_number, nullptr, &current) == 0 && current.sa_handler != SIG_IGN)
      sigaddset(&signals, signal_number);
  }
  // Before any other thread starts: threads inherit the mask, so none of
  // them takes the signal with its default action (ending the process at once).
  if (pthread_sigmask(SIG_BLOCK, &signals, nullptr) != 0) return;
  try {
    std::thread([signals]() {
      int caught = 0;
      if (sigwait(&signals, &caught) != 0) return;
      interrupted = true;
      RemoveTemporariesInFlight();
      // End as the signal would have ended the program (status 128 + signal
      // for the shell): its default action, delivered to this thread.
      signal(caught, SIG_DFL);
      pthread_sigmask(SIG_UNBLOCK, &signals, nullptr);
      raise(caught);
    }).detach();
  } catch (const std::system_error&) {
    // No thread to take them: the signals keep their default action.
    pthread_sigmask(SIG_UNBLOCK, &signals, nullptr);
  }
}

}  // namespace handeye::tools
