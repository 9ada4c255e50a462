#include "io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace flexref::io {
namespace {

/// "" for a regular file, otherwise what the file is and why it is refused.
std::string refusal(const struct stat& st, const std::string& what) {
  if (S_ISREG(st.st_mode)) return "";
  const std::string expected = "; expected " + what + " (a regular file)";
  if (S_ISDIR(st.st_mode)) return "is a directory" + expected;
  if (S_ISFIFO(st.st_mode)) {
    return "is a FIFO (named pipe), not a regular file: reading it could wait for ever" + expected +
           "; save its contents to a file first";
  }
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) {
    return std::string("is a ") + (S_ISCHR(st.st_mode) ? "character" : "block") +
           " device, not a regular file: it may never end" + expected;
  }
  if (S_ISSOCK(st.st_mode)) return "is a socket, not a regular file" + expected;
  return "is not a regular file" + expected;
}

}  // namespace

/// Reads the descriptor in blocks of 64 KiB.
class InputFile::Buffer : public std::streambuf {
 public:
  explicit Buffer(int fd) : fd_(fd), data_(1 << 16) {}
  bool failed() const { return error_ != 0; }
  int error() const { return error_; }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    ssize_t n = 0;
    do {
      n = ::read(fd_, data_.data(), data_.size());
    } while (n < 0 && errno == EINTR);
    if (n <= 0) {
      if (n < 0) error_ = errno;
      return traits_type::eof();
    }
    setg(data_.data(), data_.data(), data_.data() + n);
    return traits_type::to_int_type(*gptr());
  }

 private:
  int fd_;
  std::vector<char> data_;
  int error_ = 0;
};

InputFile::InputFile(const std::string& path, const std::string& what)
    : std::istream(nullptr), path_(path) {
  struct stat st {};
  // Checked before opening (opening a device can have effects, a FIFO's open waits for a
  // writer) and again on the descriptor, in case the path changed in between.
  if (::stat(path.c_str(), &st) != 0) {
    error_ = std::string("cannot open ") + what + ": " + std::strerror(errno);
  } else if (error_ = refusal(st, what); error_.empty()) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
      error_ = std::string("cannot open ") + what + ": " + std::strerror(errno);
    } else if (::fstat(fd_, &st) != 0 || !(error_ = refusal(st, what)).empty()) {
      if (error_.empty()) error_ = std::strerror(errno);
      ::close(fd_);
      fd_ = -1;
    }
  }
  if (fd_ < 0) {
    setstate(std::ios::failbit);
    return;
  }
  buffer_ = std::make_unique<Buffer>(fd_);
  rdbuf(buffer_.get());
}

InputFile::~InputFile() {
  rdbuf(nullptr);
  if (fd_ >= 0) ::close(fd_);
}

std::string InputFile::read_all() {
  std::string text;
  if (fd_ < 0) throw std::runtime_error(path_ + ": " + error_);
  char block[1 << 16];
  while (read(block, sizeof block) || gcount() > 0) {
    text.append(block, static_cast<std::size_t>(gcount()));
  }
  if (buffer_->failed()) {
    throw std::runtime_error(path_ + ": read error: " + std::strerror(buffer_->error()));
  }
  return text;
}

}  // namespace flexref::io
