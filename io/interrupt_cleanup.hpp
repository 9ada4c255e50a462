#pragma once
/// \file interrupt_cleanup.hpp
/// What an interrupted program leaves behind: nothing. SIGINT, SIGTERM and SIGHUP (a terminal,
/// a batch system, a closed session) end the program after removing every temporary file and
/// staging folder it registered and forwarding the signal to the child programs it started.
///
/// The signals are blocked in every thread and taken by one watcher thread with sigwait(), so
/// the cleanup runs as ordinary code (std::filesystem, locks, stderr) instead of in a signal
/// handler, where only async-signal-safe calls are allowed and a recursive folder removal could
/// not be written (docs/decisions.md, "Outputs"). The program then ends by the signal itself
/// (its default action, re-raised), so the shell shows 128 + N (130 for SIGINT, 143 for
/// SIGTERM, 129 for SIGHUP) and a parent sees that it was interrupted.
#include <signal.h>
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>

namespace flexref::io {

/// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread — and so in every thread it starts
/// afterwards — and starts the watcher thread that takes them. Call it first in main(), before
/// any thread exists (a thread started earlier would take the signal and die without the
/// cleanup). A signal ignored at startup (nohup, a background job of a script) stays ignored.
/// A second call does nothing.
void install_interrupt_cleanup();

/// The signal mask a child program must start with: the one before install_interrupt_cleanup
/// (a child that inherited the blocked signals could not be interrupted). The current mask
/// when it was not installed.
sigset_t child_signal_mask();

/// One entry of the cleanup: a path removed (with its contents, if a folder) or a child program
/// signalled when a signal ends the program while the entry lives. Destroying or releasing the
/// entry takes it off the list; it never removes anything itself.
class InterruptCleanup {
 public:
  InterruptCleanup() = default;
  /// Runs `create` (which makes a file or folder — mkdir, open with O_EXCL, mkstemp — and
  /// returns its path, or an empty path when it made nothing) and registers the path, both under
  /// the list's lock: when a signal's cleanup starts, a path is either created and listed or
  /// neither, so nothing created can escape the cleanup. `create` must not call into this list;
  /// its exceptions propagate and register nothing.
  static InterruptCleanup remove_path(const std::function<std::filesystem::path()>& create);
  /// Runs `start` (which starts a child program and returns the id kill() takes: the pid, or
  /// −pgid for a process group) and registers it, both under the list's lock; a signal is then
  /// forwarded to it. A start that returns 0 registers nothing. `start` runs under the lock:
  /// it must not call into this list (child_signal_mask() included — take the mask before).
  static InterruptCleanup signal_process(const std::function<pid_t()>& start);

  InterruptCleanup(InterruptCleanup&& other) noexcept;
  InterruptCleanup& operator=(InterruptCleanup&& other) noexcept;
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;
  ~InterruptCleanup();

  /// Takes the entry off the list now.
  void release();
  /// Runs `action` under the list's lock and makes the entry the path `action` returns (empty:
  /// takes the entry off the list), so that a signal's cleanup sees the files as they were
  /// before the action or after it, never between. For moves: a staging folder renamed into
  /// place, the previous folder renamed aside and now the one to remove. `action` must not call
  /// into this list; if it throws, the entry stays as it was.
  void update(const std::function<std::filesystem::path()>& action);

 private:
  explicit InterruptCleanup(std::uint64_t id) : id_(id) {}
  std::uint64_t id_ = 0;
};

}  // namespace flexref::io
