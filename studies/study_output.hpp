#pragma once
/// \file study_output.hpp
/// The output folder of a study, staged. The folder is validated before any work (so a study
/// never computes for minutes and then fails on its --out path); files are written into a
/// hidden staging folder beside it and moved into place by commit(), so an interrupted study
/// leaves either the previous folder untouched or the complete new one — never new CSVs beside
/// old plots. In a study distributed over processes (studies/mpi/distribution.hpp) only the root
/// writes: the others stage into a private temporary folder, draw no plot, and share the root's
/// outcome of the checks and of commit().
///
/// `--out` follows the output rule (io/output_file.hpp, docs/decisions.md "Outputs"): a
/// symbolic link to a folder stays a link and the study replaces the folder it points to; an
/// existing file, FIFO or device is refused, and so is a read-only folder. The staging folder
/// (and, during commit, the previous folder moved aside) is removed if SIGINT, SIGTERM or SIGHUP
/// ends the program (io/interrupt_cleanup.hpp).
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "io/interrupt_cleanup.hpp"
#include "studies/plot.hpp"
#include "studies/study_record.hpp"

namespace flexref::studies {

class StudyOutput {
 public:
  /// Checks that `dir` is absent, empty or a previous study's folder (study.toml and only .csv,
  /// .txt, .toml and .png files) and that its parent can be created and written, and creates
  /// the staging folder. Throws io::OutputError naming the path and the reason (on every
  /// process of a distributed study).
  explicit StudyOutput(std::filesystem::path dir);
  /// Removes the staging folder when commit() was not reached (an exception unwound the study).
  ~StudyOutput();
  StudyOutput(const StudyOutput&) = delete;
  StudyOutput& operator=(const StudyOutput&) = delete;

  /// Where `file` is staged (for writers that take a path, such as plot scripts).
  std::string staged(const std::string& file) const;
  /// Where `file` will be after commit() (through --out as given, links not followed).
  std::string final_path(const std::string& file) const;
  /// `text` (a message) with every path into the staging folder replaced by its final path: the
  /// staging folder no longer exists when the user reads it.
  std::string with_final_paths(std::string text) const;
  /// Writes a text file into the staging folder (atomically) and lists it in the record.
  /// Throws io::OutputError naming the file's final path.
  void write(const std::string& file, const std::string& text);
  /// Runs `writer` on staged(file) (a writer that takes a path, such as write_csv) and lists the
  /// file; an io::OutputError it throws names the file's final path.
  void write_with(const std::string& file,
                  const std::function<void(const std::string& path)>& writer);
  /// Notes a file that a writer put at staged(file) itself.
  void add(const std::string& file);
  /// Runs a bundled plot script (studies/plot.hpp) that writes `png` (a file name in the
  /// folder); `arguments` name files by staged(). On success the PNG is listed and the outcome's
  /// message is its final path; either way the outcome goes into the record's [plot] table.
  PlotOutcome plot(const std::string& script, const std::string& png,
                   std::vector<std::string> arguments);
  /// The files written so far, in order.
  const std::vector<std::string>& files() const { return files_; }

  /// Writes `record` as study.toml, with a [files] table listing every file of the study and a
  /// [plot] table with each plot's outcome, then replaces the output folder by the staging
  /// folder. Throws io::OutputError.
  void commit(StudyRecord record);

 private:
  void prepare();
  void commit_files(StudyRecord record);

  bool writer_ = true;            ///< the root process: the one that writes the folder
  std::filesystem::path dir_;     ///< --out as given, made absolute
  std::filesystem::path target_;  ///< the folder replaced: dir_ with its links followed
  std::filesystem::path staging_;
  io::InterruptCleanup staging_cleanup_;  ///< the staging folder, then the previous one
  std::vector<std::string> files_;
  std::vector<std::pair<std::string, std::string>> plots_;  ///< (png, final path or why not)
  bool committed_ = false;
};

}  // namespace flexref::studies
