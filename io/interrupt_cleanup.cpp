#include "io/interrupt_cleanup.hpp"

#include <pthread.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

namespace flexref::io {
namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

struct Entry {
  std::filesystem::path path;  ///< removed, or empty
  pid_t process = 0;           ///< signalled (kill's argument), or 0
};

/// The list of entries. Never destroyed: the watcher may run while static objects are being
/// destroyed at exit.
struct Registry {
  std::mutex mutex;
  std::map<std::uint64_t, Entry> entries;
  std::uint64_t next_id = 1;
  bool installed = false;
  sigset_t child_mask{};
};

Registry& registry() {
  static Registry* r = new Registry();
  return *r;
}

std::uint64_t add(Entry entry) {
  // Called with the lock held.
  Registry& r = registry();
  const std::uint64_t id = r.next_id++;
  r.entries.emplace(id, std::move(entry));
  return id;
}

/// Removes `path` with its contents. A child that has not yet died of the forwarded signal may
/// still add a file to a folder being removed (remove_all then fails with "not empty"): retried
/// for up to about a second.
void remove_with_retries(const std::filesystem::path& path) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
    if (!ec || !std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

/// The watcher: waits for one of the signals, forwards it to the registered children, removes
/// the registered paths, then ends the program by the signal. The list's lock is never released:
/// no path can be created or moved into place once the cleanup has started.
[[noreturn]] void watch(sigset_t set) {
  int signal_number = 0;
  while (sigwait(&set, &signal_number) != 0) {
  }
  Registry& r = registry();
  r.mutex.lock();
  int removed = 0;
  for (auto it = r.entries.rbegin(); it != r.entries.rend(); ++it) {
    if (it->second.process != 0) ::kill(it->second.process, signal_number);
  }
  for (auto it = r.entries.rbegin(); it != r.entries.rend(); ++it) {
    if (it->second.path.empty()) continue;
    remove_with_retries(it->second.path);
    ++removed;
  }
  std::fprintf(stderr, "flexref: interrupted (%s)%s\n", strsignal(signal_number),
               removed > 0 ? "; unfinished outputs removed, nothing was replaced" : "");
  std::fflush(stderr);
  // End by the signal itself: its default action, in this thread, where it is now unblocked.
  ::signal(signal_number, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, signal_number);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  ::raise(signal_number);
  _exit(128 + signal_number);
}

}  // namespace

void install_interrupt_cleanup() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  if (r.installed) return;
  pthread_sigmask(SIG_SETMASK, nullptr, &r.child_mask);
  sigset_t set;
  sigemptyset(&set);
  for (const int s : kSignals) {
    struct sigaction current {};
    // A signal ignored at startup stays ignored (blocking it would not change that: an ignored
    // signal is discarded, not queued for sigwait).
    if (sigaction(s, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
    sigaddset(&set, s);
  }
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  try {
    std::thread(watch, set).detach();
  } catch (const std::system_error&) {
    // No thread to take them: the signals keep their default action (no cleanup).
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    return;
  }
  r.installed = true;
}

sigset_t child_signal_mask() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  if (r.installed) return r.child_mask;
  sigset_t mask;
  pthread_sigmask(SIG_SETMASK, nullptr, &mask);
  return mask;
}

InterruptCleanup InterruptCleanup::remove_path(
    const std::function<std::filesystem::path()>& create) {
  const std::lock_guard<std::mutex> lock(registry().mutex);
  std::filesystem::path path = create();
  if (path.empty()) return {};
  return InterruptCleanup(add({std::move(path), 0}));
}

InterruptCleanup InterruptCleanup::signal_process(const std::function<pid_t()>& start) {
  const std::lock_guard<std::mutex> lock(registry().mutex);
  const pid_t process = start();
  if (process == 0) return {};
  return InterruptCleanup(add({{}, process}));
}

InterruptCleanup::InterruptCleanup(InterruptCleanup&& other) noexcept
    : id_(std::exchange(other.id_, 0)) {}

InterruptCleanup& InterruptCleanup::operator=(InterruptCleanup&& other) noexcept {
  if (this != &other) {
    release();
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

InterruptCleanup::~InterruptCleanup() { release(); }

void InterruptCleanup::release() {
  if (id_ == 0) return;
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  r.entries.erase(id_);
  id_ = 0;
}

void InterruptCleanup::update(const std::function<std::filesystem::path()>& action) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::filesystem::path path = action();
  if (id_ == 0) return;
  if (path.empty()) {
    r.entries.erase(id_);
    id_ = 0;
  } else {
    r.entries[id_].path = std::move(path);
  }
}

}  // namespace flexref::io
