#include "io/interrupt_cleanup.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "tests/support/temp_dir.hpp"

namespace flexref::io {
namespace {

namespace fs = std::filesystem;

/// This test's own folder (tests/support/temp_dir.hpp).
using InterruptTempDir = testing::TempDir;

/// Seconds after which a child that the signal under test did not end ends by SIGALRM: the
/// signal's path takes milliseconds (the watcher thread's cleanup, a few file removals), and
/// the sanitizer builds run it ~5× slower; 30 s is far above both.
constexpr unsigned kChildCeiling = 30;

/// Runs `body` in a child process with the cleanup installed and its stderr in `log`, and
/// returns the child's wait status. The child starts as a program does, with the signals at
/// their defaults (not Catch2's handlers) or as `ignored` leaves them, sends itself the signal
/// (a process-directed kill(), as a terminal or a batch system sends it) and waits for it: no
/// sleep, no race.
int in_child(const fs::path& log, const std::function<void()>& body, int ignored = 0) {
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int err = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (err >= 0) ::dup2(err, STDERR_FILENO);
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) ::signal(s, s == ignored ? SIG_IGN : SIG_DFL);
    install_interrupt_cleanup();
    body();
    // The signal ends the process in the watcher; this thread only waits. Should the cleanup
    // not end it (a regression), SIGALRM does after kChildCeiling, and the checks on the
    // status fail instead of waitpid waiting for ever.
    ::alarm(kChildCeiling);
    for (;;) ::pause();
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  return status;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST_CASE("SIGINT, SIGTERM and SIGHUP remove the registered paths and end the program",
          "[io][signals]") {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    INFO("signal " << signal_number);
    InterruptTempDir tmp;
    const fs::path staging = tmp.path() / ".out.staging-1";
    const fs::path temp = tmp.path() / ".run.csv.tmp-1";
    const fs::path released = tmp.path() / "released";
    const fs::path kept = tmp.path() / "kept.csv";
    const int status = in_child(tmp.path() / "stderr.txt", [&] {
      // Entries that live until the signal (never destroyed: the process ends in the watcher).
      static InterruptCleanup folder, file;
      folder = InterruptCleanup::remove_path([&] {
        fs::create_directory(staging);
        return staging;
      });
      std::ofstream(staging / "convergence.csv") << "scheme\n";
      fs::create_directory(staging / "nested");
      file = InterruptCleanup::remove_path([&] {
        std::ofstream(temp) << "half";
        return temp;
      });
      InterruptCleanup::remove_path([&] {
        fs::create_directory(released);
        return released;
      }).release();
      std::ofstream(kept) << "a user's file\n";
      ::kill(::getpid(), signal_number);
    });
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal_number);
    CHECK_FALSE(fs::exists(staging));
    CHECK_FALSE(fs::exists(temp));
    CHECK(fs::exists(released));  // taken off the list: not the cleanup's any more
    CHECK(read(kept) == "a user's file\n");
    CHECK(read(tmp.path() / "stderr.txt").find("flexref: interrupted") != std::string::npos);
  }
}

TEST_CASE("a signal is forwarded to the registered child programs", "[io][signals]") {
  InterruptTempDir tmp;
  // The grandchild holds the write end of a pipe: its end (by the forwarded signal) and the
  // child's close the pipe, and the read below returns.
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  const int status = in_child(tmp.path() / "stderr.txt", [&] {
    static InterruptCleanup program;
    // The mask a spawned program gets: SIGTERM unblocked.
    const sigset_t mask = child_signal_mask();
    program = InterruptCleanup::signal_process([&] {
      const pid_t grandchild = ::fork();
      if (grandchild == 0) {
        ::close(fds[0]);
        pthread_sigmask(SIG_SETMASK, &mask, nullptr);
        // Unless the forwarded SIGTERM ends it first (the read below then returns at once),
        // SIGALRM ends it, closing the pipe: the read never waits for ever.
        ::alarm(kChildCeiling);
        for (;;) ::pause();
      }
      return grandchild;
    });
    ::close(fds[0]);
    ::kill(::getpid(), SIGTERM);
  });
  ::close(fds[1]);
  char c = 0;
  CHECK(::read(fds[0], &c, 1) == 0);  // EOF: every writer has ended
  ::close(fds[0]);
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGTERM);
}

TEST_CASE("a signal ignored at startup stays ignored", "[io][signals]") {
  InterruptTempDir tmp;
  const fs::path staging = tmp.path() / "staging";
  const int status = in_child(
      tmp.path() / "stderr.txt",
      [&] {
        static InterruptCleanup folder;
        folder = InterruptCleanup::remove_path([&] {
          fs::create_directory(staging);
          return staging;
        });
        ::kill(::getpid(), SIGHUP);  // discarded
        std::ofstream(tmp.path() / "after_sighup") << "still running\n";
        ::kill(::getpid(), SIGTERM);
      },
      SIGHUP);  // as nohup leaves it
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGTERM);
  CHECK(fs::exists(tmp.path() / "after_sighup"));
  CHECK_FALSE(fs::exists(staging));
}

}  // namespace
}  // namespace flexref::io
