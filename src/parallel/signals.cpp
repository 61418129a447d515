#include "parallel/signals.hpp"

#include <signal.h>  // sigaction (POSIX)

#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <string>

namespace ajx::parallel {

namespace {

// A signal handler may only touch lock-free atomics.
static_assert(std::atomic<bool>::is_always_lock_free);
std::atomic<std::atomic<bool>*> g_stop_flag{nullptr};
static_assert(std::atomic<std::atomic<bool>*>::is_always_lock_free);

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGUSR1};

extern "C" void on_stop_signal(int sig) {
  std::atomic<bool>* flag = g_stop_flag.load();
  const bool already = flag == nullptr || flag->exchange(true);
  // A repeated SIGINT/SIGTERM means "now": default action (termination). SIGUSR1 only asks.
  if (already && sig != SIGUSR1) {
    std::signal(sig, SIG_DFL);  // async-signal-safe, like raise
    std::raise(sig);
  }
}

void set_action(int sig, void (*handler)(int)) {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // blocking system calls resume instead of failing with EINTR
  if (sigaction(sig, &sa, nullptr) != 0)
    throw std::runtime_error("sigaction failed for signal " + std::to_string(sig) + ": " + std::strerror(errno));
}

}  // namespace

void install_stop_handlers(std::atomic<bool>& flag) {
  g_stop_flag.store(&flag);
  for (int sig : kStopSignals) set_action(sig, on_stop_signal);
}

void ignore_stop_signals() {
  for (int sig : kStopSignals) set_action(sig, SIG_IGN);
}

void restore_default_signals() {
  for (int sig : kStopSignals) set_action(sig, SIG_DFL);
  g_stop_flag.store(nullptr);
}

}  // namespace ajx::parallel
