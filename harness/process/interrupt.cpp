#include "harness/process/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <string>

namespace hb {

namespace {

volatile sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int signal_number) {
  if (g_signal != 0) _exit(128 + signal_number);  // asked twice: stop now
  g_signal = signal_number;
}

}  // namespace

Interrupted::Interrupted(int signal_number)
    : std::runtime_error(std::string("interrupted by ") + strsignal(signal_number)),
      signal(signal_number) {}

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: a blocking wait returns early
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int interrupt_signal() { return g_signal; }

}  // namespace hb
