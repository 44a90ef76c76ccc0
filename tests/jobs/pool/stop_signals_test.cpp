// SIGINT and SIGTERM as a stop request (jobs/pool/stop_signals.h). Each case runs in a
// forked child, so the signals it raises never reach the test runner; the child reports
// through its exit code or the signal that ended it.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <functional>

#include "jobs/pool/stop_signals.h"

namespace ringtol::jobs {
namespace {

// What ended a child: the code it exited with, or the signal that killed it.
struct End {
  bool signalled = false;
  int value = -1;  // exit code, or signal number when signalled
};

End InChild(const std::function<int()>& body) {
  const pid_t child = fork();
  if (child == 0) _exit(body());
  int status = 0;
  waitpid(child, &status, 0);
  return WIFSIGNALED(status) ? End{true, WTERMSIG(status)} : End{false, WEXITSTATUS(status)};
}

constexpr int kAlive = 7;  // the child's exit code when every check inside it passed

TEST(StopSignals, TheFirstSignalIsOnlyRecordedAndTheProcessGoesOn) {
  for (const int signal : {SIGINT, SIGTERM}) {
    const End end = InChild([signal] {
      const StopSignals watch(StopSignals::Repeat::kEndsAtOnce);
      if (watch.received() != 0) return 1;
      raise(signal);
      return watch.received() == signal ? kAlive : 2;
    });
    EXPECT_FALSE(end.signalled) << StopSignals::Name(signal);
    EXPECT_EQ(end.value, kAlive) << StopSignals::Name(signal);
  }
}

TEST(StopSignals, ASecondSignalEndsTheProcessAtOnceByThatSignal) {
  const End end = InChild([] {
    const StopSignals watch(StopSignals::Repeat::kEndsAtOnce);
    raise(SIGINT);
    raise(SIGTERM);
    return kAlive;
  });
  EXPECT_TRUE(end.signalled);
  EXPECT_EQ(end.value, SIGTERM);
}

TEST(StopSignals, UnderALauncherRepeatsAreIgnoredAndTheFirstIsKept) {
  const End end = InChild([] {
    const StopSignals watch(StopSignals::Repeat::kIgnored);
    raise(SIGTERM);
    raise(SIGTERM);
    raise(SIGINT);
    return watch.received() == SIGTERM ? kAlive : 2;
  });
  EXPECT_FALSE(end.signalled);
  EXPECT_EQ(end.value, kAlive);
}

TEST(StopSignals, AfterTheWatchEndsASignalTakesItsDefaultActionAgain) {
  const End end = InChild([] {
    { const StopSignals watch(StopSignals::Repeat::kIgnored); }
    raise(SIGINT);
    return kAlive;
  });
  EXPECT_TRUE(end.signalled);
  EXPECT_EQ(end.value, SIGINT);
}

TEST(StopSignals, ExitCodesFollowTheShellConvention) {
  EXPECT_EQ(StopSignals::ExitCode(SIGINT), 130);
  EXPECT_EQ(StopSignals::ExitCode(SIGTERM), 143);
  EXPECT_EQ(StopSignals::Name(SIGTERM), "SIGTERM");
}

}  // namespace
}  // namespace ringtol::jobs
