#include "io/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <random>
#include <system_error>

#include "io/interrupt_cleanup.hpp"

namespace flexref::io {
namespace fs = std::filesystem;
namespace {

/// Symbolic links followed before giving up (Linux's own limit, MAXSYMLINKS).
constexpr int kMaxLinks = 40;

std::string error_text(int error) { return std::strerror(error); }

/// "PATH" or "PATH (a symbolic link to TARGET)", for messages.
std::string named(const std::string& path, const fs::path& target) {
  if (target == fs::path(path)) return path;
  std::error_code ec;
  const fs::path shown = fs::weakly_canonical(target, ec);
  return path + " (a symbolic link to " + (ec ? target : shown).string() + ")";
}

[[noreturn]] void fail(const std::string& what, const std::string& why) {
  throw OutputError("cannot write " + what + ": " + why);
}

/// Nobody may write it according to its permission bits. Root could, but the bits say the
/// owner wants the file or folder left alone (vim refuses to write a read-only file for root
/// too); a read-only file system fails access(W_OK) for root as well.
bool read_only_bits(const struct stat& st) {
  return (st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0;
}

/// Writes all of `text` to `fd`; returns 0, or the errno of the failed write.
int write_all(int fd, const std::string& text) {
  const char* p = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

std::string random_suffix() {
  thread_local std::mt19937_64 rng{std::random_device{}()};
  return std::to_string(rng() % 1000000000u);
}

/// A character device or a FIFO, written in place. A FIFO without a reader would block the
/// open: say so on stderr, then wait as a shell redirection does.
void write_special(const OutputTarget& t, const std::string& text, const std::string& what) {
  int fd = ::open(t.target.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0 && errno == ENXIO && t.description == "a FIFO") {
    std::fprintf(stderr, "flexref: waiting for a reader of the FIFO %s\n", what.c_str());
    std::fflush(stderr);
    do {
      fd = ::open(t.target.c_str(), O_WRONLY | O_CLOEXEC);
    } while (fd < 0 && errno == EINTR);
  }
  if (fd < 0) fail(what, error_text(errno));
  // Blocking writes from here on (a FIFO's reader may be slower than we are).
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  const int error = write_all(fd, text);
  if (::close(fd) != 0 && error == 0) fail(what, error_text(errno));
  if (error != 0) fail(what, error_text(error));
}

/// A regular file (or a new one): a temporary beside the target, renamed onto it when complete.
/// The temporary is listed for removal if a signal ends the program meanwhile.
void write_atomically(const OutputTarget& t, const std::string& text, const std::string& what) {
  const fs::path directory = t.target.has_parent_path() ? t.target.parent_path() : fs::path(".");
  struct stat existing {};
  const bool exists = ::stat(t.target.c_str(), &existing) == 0;
  fs::path temp;
  int fd = -1;
  InterruptCleanup entry;
  for (int attempt = 0; fd < 0; ++attempt) {
    temp = directory / ("." + t.target.filename().string() + ".tmp-" + random_suffix());
    int error = 0;
    entry = InterruptCleanup::remove_path([&] {
      fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      error = errno;
      return fd < 0 ? fs::path() : temp;
    });
    if (fd >= 0) break;
    if (error != EEXIST || attempt == 100) {
      fail(what,
           "cannot create a temporary file in " + directory.string() + ": " + error_text(error));
    }
  }
  // The replaced file keeps its permission bits (the temporary got the umask's).
  int error = exists && ::fchmod(fd, existing.st_mode & 07777) != 0 ? errno : 0;
  if (error == 0) error = write_all(fd, text);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    ::unlink(temp.c_str());
    entry.release();
    fail(what, error_text(error));
  }
  if (::rename(temp.c_str(), t.target.c_str()) != 0) {
    error = errno;
    ::unlink(temp.c_str());
    entry.release();
    fail(what, "cannot move the finished file into place: " + error_text(error));
  }
  entry.release();
}

/// The descriptor N when `path` names one of this program's own: /dev/stdout, /dev/stderr,
/// /dev/stdin, /dev/fd/N, /proc/self/fd/N, /proc/PID/fd/N with PID this process.
std::optional<int> own_descriptor(const std::string& path) {
  if (path == "/dev/stdin") return 0;
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  const std::string pid = "/proc/" + std::to_string(::getpid()) + "/fd/";
  for (const std::string& prefix : {std::string("/dev/fd/"), std::string("/proc/self/fd/"), pid}) {
    if (path.rfind(prefix, 0) != 0 || path.size() == prefix.size() ||
        path.size() > prefix.size() + 9) {
      continue;
    }
    const std::string number = path.substr(prefix.size());
    if (number.find_first_not_of("0123456789") != std::string::npos) continue;
    return std::stoi(number);
  }
  return std::nullopt;
}

/// follow_links, stopping at a path that names one of the program's descriptors (their links
/// lead to "pipe:[…]" or to the file behind the descriptor, which is not what the user named).
fs::path follow(const fs::path& path, std::optional<int>* descriptor) {
  fs::path current = path;
  for (int hops = 0;; ++hops) {
    if (descriptor != nullptr) {
      *descriptor = own_descriptor(current.string());
      if (*descriptor) return current;
    }
    struct stat st {};
    if (::lstat(current.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return current;
    if (hops == kMaxLinks) fail(path.string(), "too many levels of symbolic links");
    std::error_code ec;
    const fs::path link = fs::read_symlink(current, ec);
    if (ec) fail(path.string(), "cannot read the symbolic link " + current.string());
    current = link.is_absolute() ? link : current.parent_path() / link;
  }
}

}  // namespace

fs::path follow_links(const fs::path& path) { return follow(path, nullptr); }

void check_writable_directory(const fs::path& directory, const std::string& what) {
  struct stat st {};
  if (::stat(directory.c_str(), &st) != 0) {
    if (errno == ENOENT) fail(what, "directory " + directory.string() + " does not exist");
    if (errno == ENOTDIR) fail(what, directory.string() + " is not a directory");
    fail(what, directory.string() + ": " + error_text(errno));
  }
  if (!S_ISDIR(st.st_mode)) fail(what, directory.string() + " is not a directory");
  if (read_only_bits(st)) {
    fail(what, "directory " + directory.string() +
                   " is read-only (its permission bits grant no write access)");
  }
  if (::access(directory.c_str(), W_OK | X_OK) != 0) {
    fail(what, "directory " + directory.string() + " is not writable (" + error_text(errno) + ")");
  }
}

OutputTarget resolve_output(const std::string& path) {
  if (path.empty()) throw OutputError("cannot write an output file: the path is empty");
  OutputTarget t;
  t.named = path;
  std::optional<int> descriptor;
  if (path == "-") {
    descriptor = 1;
  } else {
    t.target = follow(path, &descriptor);
  }
  if (descriptor) {
    t.kind = OutputTarget::Kind::kDescriptor;
    t.descriptor = *descriptor;
    t.description = *descriptor == 1   ? "standard output"
                    : *descriptor == 2 ? "standard error"
                                       : "descriptor " + std::to_string(*descriptor);
    const int flags = ::fcntl(*descriptor, F_GETFL);
    if (flags < 0) fail(path, t.description + " is not open");
    if ((flags & O_ACCMODE) == O_RDONLY) fail(path, t.description + " is open for reading only");
    return t;
  }
  const std::string what = named(path, t.target);
  struct stat st {};
  if (::stat(t.target.c_str(), &st) != 0) {
    if (errno != ENOENT && errno != ENOTDIR) fail(what, error_text(errno));
    // Nothing there yet: a new file in an existing, writable directory.
    t.kind = OutputTarget::Kind::kFile;
    t.description = "a new file";
    check_writable_directory(t.target.has_parent_path() ? t.target.parent_path() : fs::path("."),
                             what);
    return t;
  }
  if (S_ISDIR(st.st_mode)) fail(what, "it is a directory; give a file name");
  if (S_ISBLK(st.st_mode))
    fail(what, "it is a block device (a disk); flexref does not write disks");
  if (S_ISSOCK(st.st_mode)) {
    fail(what, "it is a socket; give a file, a FIFO or - (standard output)");
  }
  if (!S_ISREG(st.st_mode) && !S_ISCHR(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    fail(what, "it is neither a file, a FIFO nor a character device");
  }
  if (read_only_bits(st)) {
    fail(what,
         "it is read-only (its permission bits grant no write access); make it writable "
         "or give another name");
  }
  if (::access(t.target.c_str(), W_OK) != 0) fail(what, "not writable (" + error_text(errno) + ")");
  if (S_ISREG(st.st_mode)) {
    t.kind = OutputTarget::Kind::kFile;
    t.description = "a file";
    // Replaced by a rename: its directory must take the temporary.
    check_writable_directory(t.target.has_parent_path() ? t.target.parent_path() : fs::path("."),
                             what);
  } else {
    t.kind = OutputTarget::Kind::kSpecial;
    t.description = S_ISFIFO(st.st_mode) ? "a FIFO" : "a character device";
  }
  return t;
}

void check_writable_file(const std::string& path) { (void)resolve_output(path); }

void write_output_file(const std::string& path, const std::string& text) {
  const OutputTarget t = resolve_output(path);
  const std::string what = named(path, t.target);
  switch (t.kind) {
    case OutputTarget::Kind::kDescriptor:
      std::cout.flush();
      std::fflush(stdout);
      std::cerr.flush();
      if (const int error = write_all(t.descriptor, text); error != 0) {
        fail(path + " (" + t.description + ")", error_text(error));
      }
      return;
    case OutputTarget::Kind::kSpecial:
      write_special(t, text, what);
      return;
    case OutputTarget::Kind::kFile:
      write_atomically(t, text, what);
      return;
  }
}

std::optional<std::string> sidecar_path(const std::string& output) {
  const OutputTarget t = resolve_output(output);
  if (t.kind != OutputTarget::Kind::kFile) return std::nullopt;
  return t.target.string() + ".meta.toml";
}

}  // namespace flexref::io
