/// \file mpi_session.cpp
/// The MPI distribution and process session (studies/mpi/distribution.hpp, docs/mpi.md). Compiled
/// only when CMake finds MPI (option FLEXREF_MPI); studies/mpi/serial_session.cpp replaces it
/// otherwise. Only this file includes <mpi.h>.
///
/// Scheduling is dynamic, because the cost of a study's tasks varies by orders of magnitude
/// (an lte-map point at high spin takes many more steps than one at low spin): rank 0 hands
/// out task indices one at a time on request, to its own worker threads through a shared
/// counter and to the other ranks by messages. Only the main thread of a process calls MPI
/// (MPI_THREAD_FUNNELED); worker threads on the other ranks ask their main thread for work.
/// Every wait for a message polls (MPI_Test/MPI_Iprobe and a sleep of kPoll) instead of
/// blocking, because a blocking MPI wait spins at 100 % of a core that the workers need.
#include <mpi.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "studies/mpi/distribution.hpp"

namespace flexref::studies {
namespace {

constexpr int kTagRequest = 11;
constexpr int kTagAssign = 12;
constexpr auto kPoll = std::chrono::microseconds(500);
/// How long a process that failed alone waits at the end for the others before it aborts the
/// job (they are then stuck waiting for it): long enough for processes that failed the same
/// way to arrive (they run the same code on the same input).
constexpr auto kExitWait = std::chrono::seconds(10);

/// Started by an MPI launcher: OpenMPI's mpirun, PMIx (srun --mpi=pmix, OpenMPI 4/5), PMI-1/2
/// (srun --mpi=pmi2, MPICH's hydra).
bool launched_by_mpi() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(variable) != nullptr) return true;
  }
  return false;
}

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw std::runtime_error(std::string("MPI: ") + what +
                             " failed: " + std::string(text, static_cast<std::size_t>(length)));
  }
}

/// Waits for a request by polling; returns false when `deadline` passed first.
bool wait(MPI_Request& request, std::chrono::steady_clock::time_point deadline =
                                    std::chrono::steady_clock::time_point::max()) {
  while (true) {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MPI_Test");
    if (done) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(kPoll);
  }
}

/// A failure of a task or a root action, as bytes.
enum class ErrorKind : std::int64_t { kInput = 1, kSolver = 2, kInvalidArgument = 3, kOther = 4 };

void write_error(SlotWriter& w, const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const core::InputError& e) {
    w.put_int(static_cast<std::int64_t>(ErrorKind::kInput));
    w.put(std::string(e.what()));
    w.put(e.file());
    w.put_int(static_cast<std::int64_t>(e.line()));
    w.put(e.key());
  } catch (const core::SolverError& e) {
    w.put_int(static_cast<std::int64_t>(ErrorKind::kSolver));
    w.put(std::string(e.what()));
    w.put(e.solver());
    w.put(e.time());
    w.put_int(static_cast<std::int64_t>(e.step()));
  } catch (const std::invalid_argument& e) {
    w.put_int(static_cast<std::int64_t>(ErrorKind::kInvalidArgument));
    w.put(std::string(e.what()));
  } catch (const std::exception& e) {
    w.put_int(static_cast<std::int64_t>(ErrorKind::kOther));
    w.put(std::string(e.what()));
  } catch (...) {
    w.put_int(static_cast<std::int64_t>(ErrorKind::kOther));
    w.put(std::string("unknown exception"));
  }
}

/// The exceptions rebuilt from bytes keep their type (for the exit code) and their message.
class RemoteInputError : public core::InputError {
 public:
  RemoteInputError(std::string file, int line, std::string key, std::string message)
      : core::InputError(std::move(file), line, std::move(key), ""), message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

class RemoteSolverError : public core::SolverError {
 public:
  RemoteSolverError(std::string solver, double time, long step, std::string message)
      : core::SolverError(std::move(solver), time, step, ""), message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

[[noreturn]] void throw_error(SlotReader& r) {
  const auto kind = static_cast<ErrorKind>(r.get_int());
  std::string message = r.get_string();
  switch (kind) {
    case ErrorKind::kInput: {
      std::string file = r.get_string();
      const auto line = static_cast<int>(r.get_int());
      std::string key = r.get_string();
      throw RemoteInputError(std::move(file), line, std::move(key), std::move(message));
    }
    case ErrorKind::kSolver: {
      std::string solver = r.get_string();
      const double time = r.get_double();
      const auto step = static_cast<long>(r.get_int());
      throw RemoteSolverError(std::move(solver), time, step, std::move(message));
    }
    case ErrorKind::kInvalidArgument:
      throw std::invalid_argument(message);
    case ErrorKind::kOther:
      break;
  }
  throw std::runtime_error(message);
}

class MpiDistribution final : public Distribution {
 public:
  MpiDistribution() {
    check(MPI_Comm_dup(MPI_COMM_WORLD, &comm_), "MPI_Comm_dup");
    check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
    MPI_Comm node;
    check(MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
          "MPI_Comm_split_type");
    check(MPI_Comm_size(node, &node_size_), "MPI_Comm_size");
    MPI_Comm_free(&node);
  }
  ~MpiDistribution() override { MPI_Comm_free(&comm_); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int processes_on_node() const override { return node_size_; }

  void run(int n, int jobs, const std::function<void(int)>& task, const SlotCodec& codec,
           const ProgressCallback& progress) override;
  void on_root(const std::function<void()>& action) override;

 private:
  /// The bytes of every process, gathered on every process.
  std::vector<std::string> all_gather(const std::string& mine);

  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  int size_ = 1;
  int node_size_ = 1;
};

/// What a task left on the process that ran it.
struct Outcome {
  int index = 0;
  std::exception_ptr error;
};

void MpiDistribution::run(int n, int jobs, const std::function<void(int)>& task,
                          const SlotCodec& codec, const ProgressCallback& progress) {
  if (n <= 0) return;
  const int threads = std::clamp(jobs, 1, n);
  std::mutex mutex;
  std::condition_variable changed;
  int next = 0;               // root: the next task to hand out
  int wanted = 0;             // other ranks: workers waiting for a task
  std::vector<int> assigned;  // other ranks: tasks received for the workers
  bool no_more = false;       // other ranks: the root has no task left
  int local_done = 0;
  int active = threads;
  int reported = 0;  // root: the progress reported so far
  std::vector<Outcome> outcomes;

  const auto acquire = [&]() -> int {
    std::unique_lock<std::mutex> lock(mutex);
    if (rank_ == 0) return next < n ? next++ : -1;
    ++wanted;
    changed.notify_all();
    changed.wait(lock, [&] { return !assigned.empty() || no_more; });
    --wanted;
    if (assigned.empty()) return -1;
    const int i = assigned.back();
    assigned.pop_back();
    return i;
  };
  const auto worker = [&] {
    for (int i = acquire(); i >= 0; i = acquire()) {
      Outcome outcome{i, nullptr};
      try {
        task(i);
      } catch (...) {
        outcome.error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      outcomes.push_back(std::move(outcome));
      ++local_done;
      changed.notify_all();
    }
    const std::lock_guard<std::mutex> lock(mutex);
    --active;
    changed.notify_all();
  };

  {
    std::vector<std::jthread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
    // The main thread serves the messages.
    if (rank_ == 0) {
      std::vector<int> remote_done(static_cast<std::size_t>(size_), 0);
      int finished_ranks = 0;
      while (true) {
        int flag = 0;
        MPI_Status status;
        check(MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, comm_, &flag, &status), "MPI_Iprobe");
        if (flag) {
          int done_there = 0;
          check(MPI_Recv(&done_there, 1, MPI_INT, status.MPI_SOURCE, kTagRequest, comm_,
                         MPI_STATUS_IGNORE),
                "MPI_Recv");
          remote_done[static_cast<std::size_t>(status.MPI_SOURCE)] = done_there;
          int index = -1;
          {
            const std::lock_guard<std::mutex> lock(mutex);
            if (next < n) index = next++;
          }
          if (index < 0) ++finished_ranks;
          check(MPI_Send(&index, 1, MPI_INT, status.MPI_SOURCE, kTagAssign, comm_), "MPI_Send");
        }
        int total = 0;
        bool local_finished = false;
        {
          std::unique_lock<std::mutex> lock(mutex);
          if (!flag) changed.wait_for(lock, kPoll);
          total = local_done;
          local_finished = active == 0;
        }
        for (const int d : remote_done) total += d;
        if (progress && total > reported) {
          reported = total;
          progress(std::min(total, n), n);
        }
        if (local_finished && finished_ranks == size_ - 1) break;
      }
    } else {
      while (true) {
        int done_here = 0;
        {
          std::unique_lock<std::mutex> lock(mutex);
          changed.wait_for(lock, kPoll, [&] { return (wanted > 0 && !no_more) || active == 0; });
          if (active == 0) break;
          if (wanted == 0 || no_more) continue;
          done_here = local_done;
        }
        check(MPI_Send(&done_here, 1, MPI_INT, 0, kTagRequest, comm_), "MPI_Send");
        int index = -1;
        MPI_Request request;
        check(MPI_Irecv(&index, 1, MPI_INT, 0, kTagAssign, comm_, &request), "MPI_Irecv");
        wait(request);
        const std::lock_guard<std::mutex> lock(mutex);
        if (index >= 0) {
          assigned.push_back(index);
        } else {
          no_more = true;
        }
        changed.notify_all();
      }
    }
  }  // workers joined

  // Exchange: every slot and every failure to every process.
  SlotWriter mine;
  for (const Outcome& o : outcomes) {
    mine.put_int(static_cast<std::int64_t>(o.index));
    mine.put(o.error == nullptr);
    if (o.error == nullptr) {
      SlotWriter slot;
      codec.write(o.index, slot);
      mine.put(slot.bytes());
    } else {
      SlotWriter failure;
      write_error(failure, o.error);
      mine.put(failure.bytes());
    }
  }
  const std::vector<std::string> everyone = all_gather(mine.bytes());
  int first_failure = n;
  std::string failure_bytes;
  for (int r = 0; r < size_; ++r) {
    const std::string& bytes = everyone[static_cast<std::size_t>(r)];
    SlotReader reader(bytes.data(), bytes.size());
    while (!reader.at_end()) {
      const auto index = static_cast<int>(reader.get_int());
      const bool ok = reader.get_bool();
      const std::string slot = reader.get_string();
      if (ok && r != rank_) {
        SlotReader slot_reader(slot.data(), slot.size());
        codec.read(index, slot_reader);
      } else if (!ok && index < first_failure) {
        first_failure = index;
        failure_bytes = slot;
      }
    }
  }
  if (rank_ == 0 && progress && reported < n) progress(n, n);
  if (first_failure < n) {
    set_failure_is_collective();
    for (const Outcome& o : outcomes) {
      if (o.index == first_failure) std::rethrow_exception(o.error);  // the original here
    }
    SlotReader reader(failure_bytes.data(), failure_bytes.size());
    throw_error(reader);
  }
}

std::vector<std::string> MpiDistribution::all_gather(const std::string& mine) {
  int size = static_cast<int>(mine.size());
  if (mine.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw std::runtime_error("MPI: more than 2 GB of results on one process");
  }
  std::vector<int> sizes(static_cast<std::size_t>(size_));
  MPI_Request request;
  check(MPI_Iallgather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, comm_, &request),
        "MPI_Iallgather");
  wait(request);
  std::vector<int> offsets(static_cast<std::size_t>(size_), 0);
  long long total = 0;
  for (int r = 0; r < size_; ++r) {
    offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
    total += sizes[static_cast<std::size_t>(r)];
  }
  if (total > std::numeric_limits<int>::max()) {
    throw std::runtime_error("MPI: more than 2 GB of results in a study");
  }
  std::string all(static_cast<std::size_t>(total), '\0');
  check(MPI_Iallgatherv(mine.data(), size, MPI_CHAR, all.data(), sizes.data(), offsets.data(),
                        MPI_CHAR, comm_, &request),
        "MPI_Iallgatherv");
  wait(request);
  std::vector<std::string> out;
  for (int r = 0; r < size_; ++r) {
    out.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                             static_cast<std::size_t>(sizes[static_cast<std::size_t>(r)])));
  }
  return out;
}

void MpiDistribution::on_root(const std::function<void()>& action) {
  std::exception_ptr error;
  std::string bytes;
  if (rank_ == 0) {
    try {
      action();
    } catch (...) {
      error = std::current_exception();
      SlotWriter w;
      write_error(w, error);
      bytes = w.bytes();
    }
  }
  long long size = static_cast<long long>(bytes.size());
  MPI_Request request;
  check(MPI_Ibcast(&size, 1, MPI_LONG_LONG, 0, comm_, &request), "MPI_Ibcast");
  wait(request);
  if (size == 0) return;
  bytes.resize(static_cast<std::size_t>(size));
  check(MPI_Ibcast(bytes.data(), static_cast<int>(size), MPI_CHAR, 0, comm_, &request),
        "MPI_Ibcast");
  wait(request);
  set_failure_is_collective();
  if (error) std::rethrow_exception(error);
  SlotReader reader(bytes.data(), bytes.size());
  throw_error(reader);
}

}  // namespace

struct ProcessSession::Impl {
  std::unique_ptr<MpiDistribution> distribution;
  MPI_Comm exit_comm = MPI_COMM_NULL;
  int rank = 0;
  int saved_stderr = -1;          ///< other ranks: the real standard error
  std::FILE* captured = nullptr;  ///< other ranks: their standard error, kept back
  bool finished = false;

  /// Copies what this rank wrote to its standard error to the real one, each line prefixed.
  void show_captured() const {
    if (captured == nullptr) return;
    std::fflush(stderr);
    std::rewind(captured);
    std::string out;
    char line[4096];
    while (std::fgets(line, sizeof line, captured) != nullptr) {
      out += "[rank " + std::to_string(rank) + "] " + line;
    }
    if (!out.empty() && out.back() != '\n') out += '\n';
    if (::write(saved_stderr, out.data(), out.size()) < 0) return;
  }
};

ProcessSession::ProcessSession(int& argc, char**& argv) : impl_(std::make_unique<Impl>()) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  impl_->distribution = std::make_unique<MpiDistribution>();
  check(MPI_Comm_dup(MPI_COMM_WORLD, &impl_->exit_comm), "MPI_Comm_dup");
  impl_->rank = impl_->distribution->rank();
  install_distribution(impl_->distribution.get());
  if (impl_->rank != 0) {
    // Results, tables and progress are rank 0's; the others' output would repeat them.
    if (std::freopen("/dev/null", "w", stdout) == nullptr) std::fclose(stdout);
    impl_->captured = std::tmpfile();
    if (impl_->captured != nullptr) {
      std::fflush(stderr);
      impl_->saved_stderr = ::dup(STDERR_FILENO);
      ::dup2(::fileno(impl_->captured), STDERR_FILENO);
    }
  }
}

ProcessSession::~ProcessSession() {
  if (impl_->distribution == nullptr || impl_->finished) return;
  // finish() was not reached (an exception left main): the others may wait for this process.
  impl_->show_captured();
  MPI_Abort(MPI_COMM_WORLD, 3);
}

int ProcessSession::finish(int exit_code) {
  Impl& s = *impl_;
  if (s.distribution == nullptr || s.finished) return exit_code;
  s.finished = true;
  std::fflush(stdout);
  std::fflush(stderr);
  const bool alone = exit_code != 0 && !s.distribution->failure_is_collective();
  // Every process waits here for the others: without limit after a success or a failure that
  // all processes share; at most kExitWait after a failure of its own, after which the others
  // are presumed stuck waiting for it and the job is aborted.
  MPI_Request request;
  check(MPI_Ibarrier(s.exit_comm, &request), "MPI_Ibarrier");
  if (!wait(request, alone ? std::chrono::steady_clock::now() + kExitWait
                           : std::chrono::steady_clock::time_point::max())) {
    s.show_captured();
    MPI_Abort(MPI_COMM_WORLD, exit_code);
  }
  // All here. A rank that failed while rank 0 succeeded failed alone: show why.
  int root_code = exit_code;
  check(MPI_Bcast(&root_code, 1, MPI_INT, 0, s.exit_comm), "MPI_Bcast");
  if (s.rank != 0 && exit_code != 0 && root_code == 0) s.show_captured();
  install_distribution(nullptr);
  s.distribution.reset();
  MPI_Comm_free(&s.exit_comm);
  MPI_Finalize();
  if (s.saved_stderr >= 0) {
    ::dup2(s.saved_stderr, STDERR_FILENO);
    ::close(s.saved_stderr);
  }
  return exit_code;
}

}  // namespace flexref::studies
