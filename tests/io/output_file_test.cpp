#include "io/output_file.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "tests/support/temp_dir.hpp"

namespace flexref::io {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

/// This test's own folder (tests/support/temp_dir.hpp).
using OutputFileTempDir = testing::TempDir;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The names in a folder (to see that no temporary is left behind).
std::set<std::string> names(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
  return out;
}

std::string message_of(const std::string& path) {
  try {
    check_writable_file(path);
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}

std::string write_message(const std::string& path, const std::string& text) {
  try {
    write_output_file(path, text);
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("check_writable_file refuses paths that cannot be written, before any work", "[io]") {
  OutputFileTempDir tmp;
  const fs::path& dir = tmp.path();
  std::ofstream(dir / "file.toml") << "x";

  CHECK_THAT(message_of(""), Contains("empty"));
  CHECK_THAT(message_of(dir.string()), Contains("is a directory"));
  CHECK_THAT(message_of((dir / "missing" / "x.csv").string()), Contains("does not exist"));
  // `--out base.toml/sub`: the parent is a file.
  CHECK_THAT(message_of((dir / "file.toml" / "x.csv").string()), Contains("is not a directory"));
  CHECK(message_of((dir / "x.csv").string()).empty());
  CHECK_FALSE(fs::exists(dir / "x.csv"));  // a check writes nothing
}

TEST_CASE("a regular file is replaced atomically and keeps its permission bits", "[io]") {
  OutputFileTempDir tmp;
  const fs::path file = tmp.path() / "run.csv";
  write_output_file(file.string(), "first\n");
  CHECK(read_text(file) == "first\n");
  ::chmod(file.c_str(), 0640);
  write_output_file(file.string(), "second\n");
  CHECK(read_text(file) == "second\n");
  struct stat st {};
  REQUIRE(::stat(file.c_str(), &st) == 0);
  CHECK((st.st_mode & 07777) == 0640);
  CHECK(names(tmp.path()) == std::set<std::string>{"run.csv"});  // no temporary left
}

TEST_CASE("a symbolic link stays a link and its target is written", "[io]") {
  OutputFileTempDir tmp;
  fs::create_directories(tmp.path() / "data");
  std::ofstream(tmp.path() / "data" / "real.csv") << "old\n";
  fs::create_symlink("data/real.csv", tmp.path() / "link.csv");
  // A chain: link2 -> link.csv -> data/real.csv.
  fs::create_symlink(tmp.path() / "link.csv", tmp.path() / "link2.csv");

  write_output_file((tmp.path() / "link2.csv").string(), "new\n");
  CHECK(fs::is_symlink(tmp.path() / "link.csv"));
  CHECK(fs::is_symlink(tmp.path() / "link2.csv"));
  CHECK(read_text(tmp.path() / "data" / "real.csv") == "new\n");
  CHECK(names(tmp.path() / "data") == std::set<std::string>{"real.csv"});
  // The sidecar goes beside the file written, not beside the link.
  const std::optional<std::string> sidecar = sidecar_path((tmp.path() / "link2.csv").string());
  REQUIRE(sidecar);
  CHECK(fs::path(*sidecar).filename() == "real.csv.meta.toml");
  CHECK(fs::equivalent(fs::path(*sidecar).parent_path(), tmp.path() / "data"));
}

TEST_CASE("a dangling symbolic link creates its target", "[io]") {
  OutputFileTempDir tmp;
  fs::create_directories(tmp.path() / "data");
  fs::create_symlink("data/made.csv", tmp.path() / "dangling.csv");
  write_output_file((tmp.path() / "dangling.csv").string(), "made\n");
  CHECK(fs::is_symlink(tmp.path() / "dangling.csv"));
  CHECK(read_text(tmp.path() / "data" / "made.csv") == "made\n");
  // A link into a missing folder is refused like the folder itself.
  fs::create_symlink("nowhere/x.csv", tmp.path() / "lost.csv");
  CHECK_THAT(message_of((tmp.path() / "lost.csv").string()), Contains("does not exist"));
  // A loop of links.
  fs::create_symlink("b.csv", tmp.path() / "a.csv");
  fs::create_symlink("a.csv", tmp.path() / "b.csv");
  CHECK_THAT(message_of((tmp.path() / "a.csv").string()),
             Contains("too many levels of symbolic links"));
}

TEST_CASE("a FIFO is written directly and stays a FIFO, without a sidecar", "[io]") {
  OutputFileTempDir tmp;
  const fs::path fifo = tmp.path() / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  // A reader attached first (a non-blocking open for reading does not wait for a writer), so the
  // writer's open does not wait either; the text fits in the pipe's buffer.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  REQUIRE(reader >= 0);
  CHECK_FALSE(sidecar_path(fifo.string()).has_value());
  write_output_file(fifo.string(), "t,x\n0,1\n");
  char buffer[64] = {};
  const ssize_t n = ::read(reader, buffer, sizeof buffer);
  ::close(reader);
  CHECK(std::string(buffer, n > 0 ? static_cast<std::size_t>(n) : 0) == "t,x\n0,1\n");
  struct stat st {};
  REQUIRE(::lstat(fifo.c_str(), &st) == 0);
  CHECK(S_ISFIFO(st.st_mode));
  CHECK(names(tmp.path()) == std::set<std::string>{"fifo"});
  CHECK(resolve_output(fifo.string()).kind == OutputTarget::Kind::kSpecial);
}

TEST_CASE("standard output and the program's own descriptors are written as they are", "[io]") {
  OutputFileTempDir tmp;
  // A file opened for appending, as a shell's `>>` opens it: /dev/fd/N appends to it instead of
  // replacing the file behind the descriptor.
  const fs::path log = tmp.path() / "log.csv";
  std::ofstream(log) << "previous\n";
  const int fd = ::open(log.c_str(), O_WRONLY | O_APPEND);
  REQUIRE(fd >= 0);
  const std::string path = "/dev/fd/" + std::to_string(fd);
  const OutputTarget t = resolve_output(path);
  CHECK(t.kind == OutputTarget::Kind::kDescriptor);
  CHECK(t.descriptor == fd);
  CHECK_FALSE(sidecar_path(path).has_value());
  write_output_file(path, "appended\n");
  ::close(fd);
  CHECK(read_text(log) == "previous\nappended\n");
  CHECK(names(tmp.path()) == std::set<std::string>{"log.csv"});

  // `-` is standard output (redirected here into a pipe for the check).
  int pipe_fds[2];
  REQUIRE(::pipe(pipe_fds) == 0);
  const int saved = ::dup(STDOUT_FILENO);
  ::dup2(pipe_fds[1], STDOUT_FILENO);
  const std::string message = write_message("-", "t\n0\n");
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  ::close(pipe_fds[1]);
  char buffer[16] = {};
  const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
  ::close(pipe_fds[0]);
  CHECK(message.empty());
  CHECK(std::string(buffer, n > 0 ? static_cast<std::size_t>(n) : 0) == "t\n0\n");
  CHECK(resolve_output("-").is_standard_output());
  CHECK_FALSE(sidecar_path("-").has_value());
}

TEST_CASE("read-only files and folders are refused and left untouched, for root too", "[io]") {
  OutputFileTempDir tmp;
  const fs::path file = tmp.path() / "kept.csv";
  std::ofstream(file) << "precious\n";
  ::chmod(file.c_str(), 0444);
  CHECK_THAT(message_of(file.string()), Contains("read-only"));
  CHECK_THAT(write_message(file.string(), "new\n"), Contains("read-only"));
  CHECK(read_text(file) == "precious\n");
  // Through a link as well.
  fs::create_symlink("kept.csv", tmp.path() / "link.csv");
  CHECK_THAT(write_message((tmp.path() / "link.csv").string(), "new\n"), Contains("read-only"));
  CHECK(read_text(file) == "precious\n");
  CHECK(names(tmp.path()) == std::set<std::string>{"kept.csv", "link.csv"});

  const fs::path folder = tmp.path() / "ro";
  fs::create_directories(folder);
  std::ofstream(folder / "old.csv") << "old\n";
  ::chmod(folder.c_str(), 0555);
  CHECK_THAT(write_message((folder / "new.csv").string(), "new\n"), Contains("read-only"));
  // A writable file in a read-only folder cannot be replaced atomically either.
  CHECK_THAT(write_message((folder / "old.csv").string(), "new\n"), Contains("read-only"));
  CHECK(read_text(folder / "old.csv") == "old\n");
  CHECK(names(folder) == std::set<std::string>{"old.csv"});
}

TEST_CASE("directories and sockets are refused", "[io]") {
  OutputFileTempDir tmp;
  fs::create_directories(tmp.path() / "folder");
  fs::create_symlink("folder", tmp.path() / "to_folder");
  CHECK_THAT(message_of((tmp.path() / "to_folder").string()), Contains("is a directory"));
  CHECK_THAT(message_of((tmp.path() / "to_folder").string()), Contains("symbolic link"));
  CHECK(fs::is_symlink(tmp.path() / "to_folder"));

  const fs::path socket_path = tmp.path() / "socket";
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  REQUIRE(s >= 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  REQUIRE(socket_path.string().size() < sizeof address.sun_path);
  std::strcpy(address.sun_path, socket_path.c_str());
  REQUIRE(::bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
  CHECK_THAT(write_message(socket_path.string(), "x\n"), Contains("socket"));
  ::close(s);
  CHECK(fs::is_socket(socket_path));
}

}  // namespace
}  // namespace flexref::io
