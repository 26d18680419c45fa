#include "cli/interrupt.h"

#include <csignal>
#include <unistd.h>

namespace bp {
namespace {

std::atomic<bool> g_stop{false};
bool g_announce = true;

extern "C" void on_signal(int sig) {
  if (g_stop.exchange(true)) _exit(128 + sig);  // second signal: leave now
  if (!g_announce) return;
  const char msg[] = "\nbundlepath: stopping after the current batch (press Ctrl-C again to abort)\n";
  ssize_t ignored = ::write(STDERR_FILENO, msg, sizeof msg - 1);
  (void)ignored;
}

}  // namespace

void install_interrupt_handlers(bool announce) {
  g_announce = announce;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

const std::atomic<bool>& stop_requested() { return g_stop; }

}  // namespace bp
