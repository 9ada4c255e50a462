#pragma once
/// \file distribution.hpp
/// The processes a study runs on (docs/mpi.md): this process alone, or the ranks of an MPI job.
/// The studies see only this interface; MPI itself lives in studies/mpi/ and is compiled only
/// when CMake finds MPI (FLEXREF_MPI), so the rest of the code is MPI-free.
///
/// A study hands its independent integrations to distributed_for: every task runs once on some
/// process (on `jobs` threads there), each task writes only its own result slot, and afterwards
/// every process holds every slot — sent as bytes written by the slot's codec on the process
/// that ran the task and read on the others, doubles bit for bit. The numbers therefore do not
/// depend on the number of processes or threads. The root process (rank 0) alone prints
/// progress and writes files (StudyOutput).
///
/// Failures: a task that throws is recorded with its exception's kind and message; after all
/// tasks have run, every process rethrows the exception of the failing task with the smallest
/// index (as a serial loop would have met first), so no process waits for one that stopped.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "studies/progress.hpp"

namespace flexref::studies {

/// Bytes of one result slot.
class SlotWriter {
 public:
  void put(double x);
  void put_int(std::int64_t x);
  void put(int x) { put_int(x); }
  void put(long x) { put_int(x); }
  void put(long long x) { put_int(x); }
  void put(bool x) { put_int(x ? 1 : 0); }
  void put(const std::string& s);
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

/// Reads what a SlotWriter wrote, in the same order; throws std::runtime_error when the bytes
/// end early (a codec whose read does not match its write).
class SlotReader {
 public:
  SlotReader(const char* data, std::size_t size) : data_(data), size_(size) {}
  double get_double();
  std::int64_t get_int();
  bool get_bool() { return get_int() != 0; }
  std::string get_string();
  void get(double& x) { x = get_double(); }
  void get(int& x) { x = static_cast<int>(get_int()); }
  void get(long& x) { x = static_cast<long>(get_int()); }
  void get(long long& x) { x = static_cast<long long>(get_int()); }
  void get(bool& x) { x = get_bool(); }
  void get(std::string& s) { s = get_string(); }
  bool at_end() const { return position_ == size_; }

 private:
  void need(std::size_t n) const;
  const char* data_;
  std::size_t size_;
  std::size_t position_ = 0;
};

/// How result slot i travels between processes.
struct SlotCodec {
  std::function<void(int, SlotWriter&)> write;
  std::function<void(int, SlotReader&)> read;
};

/// Called on the root only, one call at a time: `done` of `total` tasks finished (all
/// processes).
using ProgressCallback = std::function<void(int done, int total)>;

/// The processes of a run.
class Distribution {
 public:
  virtual ~Distribution() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Processes of this run on this machine (threads per process default to cores / this).
  virtual int processes_on_node() const = 0;
  bool is_root() const { return rank() == 0; }

  /// Runs task(i) for every i in [0, n) once over all processes, on `jobs` threads in each;
  /// see the file comment. `progress` may be empty.
  virtual void run(int n, int jobs, const std::function<void(int)>& task, const SlotCodec& codec,
                   const ProgressCallback& progress) = 0;
  /// Runs `action` on the root only; its exception, if any, is rethrown on every process.
  virtual void on_root(const std::function<void()>& action) = 0;

  /// True after run() or on_root() rethrew an exception on every process: the exit code is
  /// then the same everywhere and the processes may end normally.
  bool failure_is_collective() const { return failure_is_collective_; }

 protected:
  void set_failure_is_collective() { failure_is_collective_ = true; }

 private:
  bool failure_is_collective_ = false;
};

/// The process's distribution: this process alone unless a ProcessSession joined an MPI job.
Distribution& distribution();

/// distribution().run(n, jobs, task, codec, progress).
void distributed_for(int n, int jobs, const std::function<void(int)>& task, const SlotCodec& codec,
                     const ProgressCallback& progress = {});

/// The codec of a vector of slots `slots[i]` with free functions write_slot(SlotWriter&, const
/// T&) and read_slot(SlotReader&, T&) found by argument-dependent lookup.
template <typename T>
SlotCodec vector_codec(std::vector<T>& slots) {
  return {[&slots](int i, SlotWriter& w) { write_slot(w, slots[static_cast<std::size_t>(i)]); },
          [&slots](int i, SlotReader& r) { read_slot(r, slots[static_cast<std::size_t>(i)]); }};
}

/// A tripwire for slot codecs: does not compile when T's size changes on the platform the
/// codecs are checked on (libstdc++, x86-64), so that a field added to a result slot is added to
/// its codec too (a field left out would be default on every rank but the one that ran the
/// task). Call it in the codec with the size the codec was written for.
template <typename T, std::size_t kSize>
constexpr void require_codec_size() {
#if defined(__GLIBCXX__) && defined(__x86_64__)
  static_assert(sizeof(T) == kSize,
                "a field was added to or removed from a result slot: update its codec (every "
                "field), then this size");
#endif
}

/// The progress line of a distributed study: studies/progress.hpp's Progress (quiet under 2 s, a
/// redrawn line on a terminal, a line every 5 s otherwise), fed with the task counts of every
/// process, printed by the root only. finish() ends the line ("done").
class ProgressLine {
 public:
  ProgressLine(std::string label, std::string unit, bool enabled);
  /// The callback for distributed_for; a study of several distributed_for calls passes the
  /// tasks before this one (`offset`) and the study's total.
  ProgressCallback callback(int offset = 0, int total = 0);
  void finish() { progress_.finish(); }

 private:
  Progress progress_;
};

/// The process's part in an MPI job, started once at the top of main(). In a build with MPI, and
/// when flexref was started by an MPI launcher (mpirun, mpiexec, srun: found by their
/// environment variables), it initializes MPI, installs the MPI distribution, and silences the
/// standard output of ranks other than 0 (their standard error is kept back and shown only when
/// that rank alone failed). Otherwise it does nothing.
class ProcessSession {
 public:
  ProcessSession(int& argc, char**& argv);
  ~ProcessSession();
  ProcessSession(const ProcessSession&) = delete;
  ProcessSession& operator=(const ProcessSession&) = delete;

  /// Ends the session with the command's exit code and returns the process's. After a failure
  /// that was not collective (one process failed alone, e.g. reading a file only it cannot
  /// see), the processes wait a while for each other and then abort the whole job rather than
  /// hang (docs/mpi.md, "Failures").
  int finish(int exit_code);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// Installs `d` as the process's distribution (nullptr: back to this process alone). For
/// ProcessSession implementations and tests.
void install_distribution(Distribution* d);

}  // namespace flexref::studies
