#pragma once
/// \file input_file.hpp
/// Every file flexref reads (scenes, modal data, CSVs, study files, CalculiX files) is opened
/// through InputFile, which accepts regular files only (symbolic links to them included): a
/// device such as /dev/zero never ends and a FIFO blocks until someone writes to it, so a
/// reader given either would hang or fill the memory. What is not a regular file is refused
/// before it is opened — opening some devices has effects of its own — and checked again on
/// the open descriptor (docs/decisions.md, "Outputs"). Readers turn the reason into their own
/// error, naming the path (exit 1).
#include <istream>
#include <memory>
#include <streambuf>
#include <string>

namespace flexref::io {

/// A regular file opened for reading, as an std::istream. Like std::ifstream, the constructor
/// does not throw: a file that cannot be read leaves the stream failed and error() says why.
class InputFile : public std::istream {
 public:
  /// `what` names the kind of file in messages ("the scene file", "a CalculiX .frd file").
  InputFile(const std::string& path, const std::string& what);
  ~InputFile() override;
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  bool is_open() const { return fd_ >= 0; }
  /// Why the file could not be opened (empty when it was): "cannot open the scene file: No such
  /// file or directory", "is a FIFO (named pipe), not a regular file: …", "is a directory; …".
  const std::string& error() const { return error_; }
  /// The whole file (from the current position) as text. Throws std::runtime_error with the
  /// path on a read error.
  std::string read_all();

 private:
  class Buffer;
  int fd_ = -1;
  std::string path_;
  std::string error_;
  std::unique_ptr<Buffer> buffer_;
};

}  // namespace flexref::io
