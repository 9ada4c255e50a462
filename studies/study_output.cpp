#include "studies/study_output.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <random>
#include <system_error>
#include <utility>

#include "io/output_file.hpp"
#include "studies/mpi/distribution.hpp"
#include "studies/progress.hpp"

namespace flexref::studies {
namespace fs = std::filesystem;
namespace {

std::string random_suffix() {
  std::random_device rd;
  return std::to_string(rd() % 1000000000u);
}

[[noreturn]] void fail(const fs::path& path, const std::string& why) {
  throw io::OutputError("cannot write the output folder " + path.string() + ": " + why);
}

/// The folder is replaced as a whole by commit(): accept only an empty folder or a previous
/// study's (a study.toml and nothing but regular .csv, .txt, .toml and .png files), so that a
/// mistyped --out (".", a home folder, a source tree) can never be swept away.
void check_replaceable(const fs::path& dir) {
  std::error_code ec;
  bool has_record = false;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    const fs::path name = entry.path().filename();
    const std::string ext = name.extension().string();
    if (!entry.is_regular_file(ec) ||
        (ext != ".csv" && ext != ".txt" && ext != ".toml" && ext != ".png")) {
      fail(dir, "it holds " + name.string() +
                    ", which is not a file of a flexref study; choose a new or empty folder");
    }
    has_record = has_record || name == "study.toml";
  }
  if (ec) fail(dir, ec.message());
  if (!fs::is_empty(dir, ec) && !has_record) {
    fail(dir,
         "it is not empty and holds no study.toml (not a flexref study's folder); choose a "
         "new or empty folder");
  }
}

}  // namespace

StudyOutput::StudyOutput(fs::path dir) : dir_(std::move(dir)) {
  // Only the root process of a distributed study writes (studies/mpi/distribution.hpp); its checks
  // are every process's outcome, and the other processes stage into a private temporary folder
  // that they drop.
  writer_ = distribution().is_root();
  if (!writer_) {
    std::error_code ec;
    staging_ = fs::temp_directory_path(ec) /
               ("flexref-rank-" + std::to_string(distribution().rank()) + "-" + random_suffix());
    staging_cleanup_ = io::InterruptCleanup::remove_path(
        [&] { return fs::create_directories(staging_, ec) ? staging_ : fs::path(); });
  }
  try {
    distribution().on_root([this] { prepare(); });
  } catch (...) {
    if (!writer_) {
      std::error_code ignore;
      fs::remove_all(staging_, ignore);
    }
    throw;
  }
}

void StudyOutput::prepare() {
  if (dir_.empty()) fail(dir_, "the path is empty");
  std::error_code ec;
  const fs::path absolute = fs::absolute(dir_, ec);
  if (ec) fail(dir_, ec.message());
  // A link to a folder stays a link: the study replaces the folder it points to (a dangling
  // link: the folder it names is created).
  const fs::path target = io::follow_links(absolute);
  const std::string via = target == absolute ? "" : " (a symbolic link to " + target.string() + ")";
  const fs::file_status status = fs::status(target, ec);
  if (fs::exists(status) && !fs::is_directory(status)) {
    fail(dir_, "it exists and is not a directory" + via);
  }
  if (fs::is_directory(status)) {
    check_replaceable(target);
    // Replaced as a whole by a rename: a read-only folder is the user's sign to leave it alone.
    struct stat st {};
    if (::stat(target.c_str(), &st) == 0 && (st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0) {
      fail(dir_, "it is read-only" + via + " (its permission bits grant no write access)");
    }
  }
  // The nearest existing ancestor must be a directory we may write into.
  fs::path ancestor = target.parent_path();
  while (!ancestor.empty() && !fs::exists(ancestor, ec)) ancestor = ancestor.parent_path();
  if (ancestor.empty()) fail(dir_, "no existing parent directory");
  io::check_writable_directory(ancestor, "the output folder " + dir_.string());
  fs::create_directories(target.parent_path(), ec);
  if (ec) fail(dir_, "cannot create " + target.parent_path().string() + ": " + ec.message());
  staging_ =
      target.parent_path() / ("." + target.filename().string() + ".staging-" + random_suffix());
  staging_cleanup_ = io::InterruptCleanup::remove_path(
      [&] { return fs::create_directory(staging_, ec) ? staging_ : fs::path(); });
  if (ec) fail(dir_, "cannot create " + staging_.string() + ": " + ec.message());
  dir_ = absolute;
  target_ = target;
}

StudyOutput::~StudyOutput() {
  if (committed_ && writer_) return;
  std::error_code ignore;
  fs::remove_all(staging_, ignore);
}

std::string StudyOutput::staged(const std::string& file) const {
  return (staging_ / file).string();
}

std::string StudyOutput::final_path(const std::string& file) const {
  return (dir_ / file).string();
}

std::string StudyOutput::with_final_paths(std::string text) const {
  const std::string from = staging_.string();
  const std::string to = dir_.string();
  if (from.empty()) return text;
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

void StudyOutput::write(const std::string& file, const std::string& text) {
  write_with(file, [&](const std::string& path) { io::write_output_file(path, text); });
}

void StudyOutput::write_with(const std::string& file,
                             const std::function<void(const std::string& path)>& writer) {
  try {
    writer(staged(file));
  } catch (const io::OutputError& e) {
    throw io::OutputError(with_final_paths(e.what()));
  }
  add(file);
}

void StudyOutput::add(const std::string& file) {
  if (std::find(files_.begin(), files_.end(), file) == files_.end()) files_.push_back(file);
}

PlotOutcome StudyOutput::plot(const std::string& script, const std::string& png,
                              std::vector<std::string> arguments) {
  if (!writer_) return {false, "plots are drawn by rank 0"};
  PlotOutcome outcome;
  {
    const Progress progress("plot " + png, 0, "");
    outcome = run_plot_script(script, std::move(arguments), staged(png));
  }
  if (outcome.ok) {
    add(png);
    outcome.message = final_path(png);
  } else {
    outcome.message = with_final_paths(outcome.message);
  }
  plots_.emplace_back(png, outcome.ok ? std::string("written") : outcome.message);
  return outcome;
}

void StudyOutput::commit(StudyRecord record) {
  if (distribution().size() > 1) {
    record.table("run").set("processes", distribution().size());
  }
  distribution().on_root([&] { commit_files(std::move(record)); });
  committed_ = true;
}

void StudyOutput::commit_files(StudyRecord record) {
  std::vector<std::string> listed = files_;
  listed.push_back("study.toml");
  record.table("files").set("folder", dir_.string()).set("written", listed);
  for (const auto& [png, status] : plots_)
    record.table("plot").set(fs::path(png).stem().string(), status);
  write("study.toml", record.to_toml());
  // Move the previous folder aside, the new one into place, then drop the previous one: the
  // folder holds either the old study or the new one at every instant but between the two
  // renames. Both renames happen under the interrupt cleanup's lock, which then lists the
  // previous folder instead of the staging one.
  std::string error;
  fs::path previous;
  staging_cleanup_.update([&]() -> fs::path {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(target_, ec))) {
      previous = target_.parent_path() /
                 ("." + target_.filename().string() + ".previous-" + random_suffix());
      fs::rename(target_, previous, ec);
      if (ec) {
        error = "cannot move the previous results aside: " + ec.message();
        previous.clear();
        return staging_;
      }
    }
    fs::rename(staging_, target_, ec);
    if (ec) {
      error = "cannot move the new results into place: " + ec.message();
      std::error_code ignore;
      if (!previous.empty()) fs::rename(previous, target_, ignore);
      previous.clear();
      return staging_;
    }
    return previous;
  });
  if (!error.empty()) fail(dir_, error);
  if (!previous.empty()) {
    std::error_code ec;
    fs::remove_all(previous, ec);
  }
  staging_cleanup_.release();
}

}  // namespace flexref::studies
