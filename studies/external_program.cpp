#include "studies/external_program.hpp"

#include <fcntl.h>
#include <poll.h>
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
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
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

/// What a program prints, as its last `keep` bytes: read from a pipe while it runs, so that a
/// program that writes its own progress (millions of lines) needs neither memory nor disk for
/// it.
class OutputTail {
 public:
  explicit OutputTail(std::size_t keep) : keep_(keep) {}
  void append(const char* data, std::size_t n) {
    text_.append(data, n);
    if (text_.size() > 2 * keep_) text_.erase(0, text_.size() - keep_);
  }
  /// The tail as a terminal leaves it: each line as what follows its last carriage return
  /// (a progress line rewritten in place shows its final state), trailing line ends dropped,
  /// at most `max_chars` characters, starting at a line when cut ("..." marks the cut).
  std::string lines(std::size_t max_chars) const {
    std::string text;
    std::size_t begin = 0;
    while (begin <= text_.size()) {
      const auto nl = text_.find('\n', begin);
      const std::size_t end = nl == std::string::npos ? text_.size() : nl;
      std::string line = text_.substr(begin, end - begin);
      while (!line.empty() && line.back() == '\r') line.pop_back();
      const auto cr = line.rfind('\r');
      if (cr != std::string::npos) line.erase(0, cr + 1);
      text += line;
      if (nl == std::string::npos) break;
      text += '\n';
      begin = nl + 1;
    }
    while (!text.empty() && text.back() == '\n') text.pop_back();
    if (text.size() > max_chars) {
      text = text.substr(text.size() - max_chars);
      const auto nl = text.find('\n');
      text = "..." + (nl == std::string::npos ? text : text.substr(nl));
    }
    return text;
  }

 private:
  std::size_t keep_;
  std::string text_;
};

/// A pipe whose read end this process keeps (non-blocking) and whose write end the program
/// gets as its standard output and error.
class OutputPipe {
 public:
  OutputPipe() {
    if (pipe2(fds_, O_CLOEXEC) != 0) {
      throw std::runtime_error("cannot create a pipe: " + std::string(std::strerror(errno)));
    }
    fcntl(fds_[0], F_SETFL, fcntl(fds_[0], F_GETFL) | O_NONBLOCK);
  }
  ~OutputPipe() {
    for (int fd : fds_) {
      if (fd >= 0) close(fd);
    }
  }
  OutputPipe(const OutputPipe&) = delete;
  OutputPipe& operator=(const OutputPipe&) = delete;
  int read_end() const { return fds_[0]; }
  int write_end() const { return fds_[1]; }
  void close_write_end() {
    close(fds_[1]);
    fds_[1] = -1;
  }
  /// Reads what is there into `tail`; false at end of file (every writer closed its end).
  bool drain(OutputTail& tail) {
    char buffer[65536];
    while (true) {
      const ssize_t n = read(fds_[0], buffer, sizeof buffer);
      if (n > 0) {
        tail.append(buffer, static_cast<std::size_t>(n));
        continue;
      }
      if (n == 0) return false;
      return errno == EAGAIN || errno == EINTR;
    }
  }

 private:
  int fds_[2] = {-1, -1};
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
  OutputPipe output;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, output.write_end(), 1);  // stdout and stderr
  posix_spawn_file_actions_adddup2(&actions, output.write_end(), 2);  // together
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
  output.close_write_end();

  // Its output is read while it runs (a full pipe would stall it), waiting on the pipe at most
  // 50 ms at a time between looks at the process.
  OutputTail tail(64 * 1024);
  ProgramOutcome outcome;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  rusage usage{};
  bool open = true;
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
    if (open) {
      pollfd p{output.read_end(), POLLIN, 0};
      poll(&p, 1, 50);
      open = output.drain(tail);
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  // What it wrote before it exited; a child it left running in the background may hold the
  // pipe open, so this takes what is there and does not wait for the end of file.
  if (open) output.drain(tail);
  outcome.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  if (WIFEXITED(status)) outcome.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
  outcome.output_tail = tail.lines(2000);
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
  level.run = trajectory::read_run_csv(output);
  level.cpu_seconds = outcome.cpu_seconds;
  const double reported = level.run.reported_cpu_seconds;
  if (std::isfinite(reported)) {
    // wait4's times come in clock ticks of the kernel's accounting (≤ 10 ms) and the two
    // clocks are read at different moments: 10 ms + 1 % before a report is called impossible.
    if (reported > 1.01 * outcome.cpu_seconds + 0.01) {
      std::ostringstream what;
      what << "reports " << reported << " s of CPU for its integration, more than the "
           << outcome.cpu_seconds << " s the whole program used (wait4)";
      throw core::InputError(output, level.run.reported_cpu_line, "cpu_seconds", what.str());
    }
    level.cpu_seconds = reported;
    level.cpu_reported = true;
  }
  return level;
}

}  // namespace flexref::studies
