#include "jobs/pool/stop_signals.h"

#include <signal.h>

#include <atomic>
#include <cstdlib>
#include <cstdio>

namespace ringtol::jobs {
namespace {

// The handler may touch only lock-free atomics (async-signal-safe); the static_asserts
// make sure these are.
std::atomic<int> first_signal{0};
std::atomic<bool> repeat_ends_at_once{true};
std::atomic<bool> installed{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free);

constexpr int kWatched[] = {SIGINT, SIGTERM};
struct sigaction previous[sizeof(kWatched) / sizeof(kWatched[0])];

extern "C" void OnStopSignal(int number) {
  int expected = 0;
  if (first_signal.compare_exchange_strong(expected, number)) return;
  if (!repeat_ends_at_once.load()) return;
  // Both calls are async-signal-safe; the re-raised signal is delivered when this
  // handler returns, with the default action: the process ends as if never watched.
  ::signal(number, SIG_DFL);
  ::raise(number);
}

}  // namespace

StopSignals::StopSignals(Repeat repeat) {
  if (installed.exchange(true)) {
    std::fputs("StopSignals: a second watcher in one process\n", stderr);
    std::abort();
  }
  first_signal = 0;
  repeat_ends_at_once = repeat == Repeat::kEndsAtOnce;
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  for (std::size_t i = 0; i < std::size(kWatched); ++i) sigaction(kWatched[i], &action, &previous[i]);
}

StopSignals::~StopSignals() {
  for (std::size_t i = 0; i < std::size(kWatched); ++i) sigaction(kWatched[i], &previous[i], nullptr);
  installed = false;
}

int StopSignals::received() const { return first_signal.load(); }

std::string StopSignals::Name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

}  // namespace ringtol::jobs
