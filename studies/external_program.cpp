#include "studies/external_program.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/error.hpp"
#include "io/interrupt_cleanup.hpp"

extern char** environ;

namespace flexref::studies {
namespace {

std::string shell_word(const std::string& s) {
  const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./+:=@%,-", c) != nullptr;
  });
  if (plain) return s;
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

/// The last lines of a file, at most `max_chars` characters.
std::string file_tail(const std::string& path, std::size_t max_chars) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  std::string text = all.str();
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  if (text.size() > max_chars) {
    text = text.substr(text.size() - max_chars);
    const auto nl = text.find('\n');
    text = "..." + (nl == std::string::npos ? text : text.substr(nl));
  }
  return text;
}

/// A temporary file, removed when this goes out of scope (or when a signal ends the program).
class TempFile {
 public:
  TempFile() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "flexref-stderr-XXXXXX").string();
    cleanup_ = io::InterruptCleanup::remove_path([&] {
      fd_ = mkstemp(pattern.data());
      return fd_ < 0 ? std::filesystem::path() : std::filesystem::path(pattern);
    });
    if (fd_ < 0) throw std::runtime_error("cannot create a temporary file: " + pattern);
    path_ = pattern;
  }
  ~TempFile() {
    if (fd_ >= 0) close(fd_);
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }
  int fd() const { return fd_; }

 private:
  std::string path_;
  int fd_ = -1;
  io::InterruptCleanup cleanup_;
};

double seconds(const timeval& tv) {
  return static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec);
}

}  // namespace

std::string substitute_command(const std::string& command, const std::string& scene, double dt,
                               const std::string& output) {
  char dt_text[40];
  std::snprintf(dt_text, sizeof dt_text, "%.17g", dt);
  std::string out;
  bool has_dt = false, has_output = false;
  for (std::size_t i = 0; i < command.size();) {
    if (command[i] != '{') {
      out += command[i++];
      continue;
    }
    const auto close = command.find('}', i);
    const std::string name = close == std::string::npos ? "" : command.substr(i + 1, close - i - 1);
    if (name == "scene") {
      out += shell_word(scene);
    } else if (name == "dt") {
      out += dt_text;
      has_dt = true;
    } else if (name == "output") {
      out += shell_word(output);
      has_output = true;
    } else {
      throw std::invalid_argument("--external: unknown placeholder '{" + name +
                                  "}' (known: {scene}, {dt}, {output})");
    }
    i = close + 1;
  }
  if (!has_dt || !has_output) {
    throw std::invalid_argument(
        "--external: the command must contain {dt} and {output} (and "
        "usually {scene}): '" +
        command + "'");
  }
  return out;
}

ProgramOutcome run_program(const std::string& command_line, double timeout_seconds) {
  TempFile err;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, err.fd(), 1);  // stdout and stderr together
  posix_spawn_file_actions_adddup2(&actions, err.fd(), 2);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  // Its own group, killed as a whole; the signal mask flexref had before it blocked SIGINT,
  // SIGTERM and SIGHUP for its watcher (io/interrupt_cleanup.hpp), so the program stays
  // interruptible.
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK);
  posix_spawnattr_setpgroup(&attr, 0);
  const sigset_t mask = io::child_signal_mask();
  posix_spawnattr_setsigmask(&attr, &mask);
  const char* argv[] = {"/bin/sh", "-c", command_line.c_str(), nullptr};
  pid_t pid = 0;
  int rc = 0;
  // Started and listed under the cleanup's lock: a signal that ends flexref reaches its group.
  const io::InterruptCleanup group = io::InterruptCleanup::signal_process([&] {
    rc = posix_spawn(&pid, "/bin/sh", &actions, &attr, const_cast<char* const*>(argv), environ);
    return rc == 0 ? -pid : 0;
  });
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) throw std::runtime_error("cannot start /bin/sh: " + std::string(std::strerror(rc)));

  ProgramOutcome outcome;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  rusage usage{};
  auto pause = std::chrono::milliseconds(1);
  while (true) {
    const pid_t w = wait4(pid, &status, WNOHANG, &usage);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) {
      throw std::runtime_error("wait4 failed: " + std::string(std::strerror(errno)));
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (timeout_seconds > 0.0 && elapsed > timeout_seconds && !outcome.timed_out) {
      outcome.timed_out = true;
      kill(-pid, SIGKILL);
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::milliseconds(50));
  }
  outcome.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  if (WIFEXITED(status)) outcome.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
  outcome.output_tail = file_tail(err.path(), 2000);
  return outcome;
}

ExternalLevel run_external_level(const ExternalCommand& command, double dt,
                                 const std::string& output) {
  std::error_code ec;
  std::filesystem::remove(output, ec);  // never read a file an earlier run left
  const std::string line = substitute_command(command.command, command.scene, dt, output);
  const ProgramOutcome outcome = run_program(line, command.timeout_seconds);
  std::ostringstream why;
  if (outcome.timed_out) {
    why << "timed out after " << command.timeout_seconds << " s";
  } else if (outcome.signal != 0) {
    why << "killed by signal " << outcome.signal << " (" << strsignal(outcome.signal) << ")";
  } else if (outcome.exit_status != 0) {
    why << "exited with status " << outcome.exit_status;
  } else if (!std::filesystem::is_regular_file(output, ec)) {
    why << "exited with status 0 but wrote no file " << output;
  }
  if (!why.str().empty()) {
    std::string message = "`" + line + "` " + why.str();
    if (!outcome.output_tail.empty()) message += "; its output ends with:\n" + outcome.output_tail;
    throw std::runtime_error(message);
  }
  ExternalLevel level;
  level.run = read_run_csv(output);
  level.cpu_seconds = outcome.cpu_seconds;
  return level;
}

}  // namespace flexref::studies
