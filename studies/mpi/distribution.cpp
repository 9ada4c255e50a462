#include "studies/mpi/distribution.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "studies/parallel.hpp"

namespace flexref::studies {
namespace {

/// This process alone: the thread pool of parallel.hpp.
class SerialDistribution final : public Distribution {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  int processes_on_node() const override { return 1; }

  void run(int n, int jobs, const std::function<void(int)>& task, const SlotCodec& /*codec*/,
           const ProgressCallback& progress) override {
    std::mutex mutex;
    int done = 0;
    try {
      run_tasks(n, jobs, task, progress, mutex, done);
    } catch (...) {
      set_failure_is_collective();
      throw;
    }
  }

  void on_root(const std::function<void()>& action) override {
    try {
      action();
    } catch (...) {
      set_failure_is_collective();
      throw;
    }
  }

 private:
  static void run_tasks(int n, int jobs, const std::function<void(int)>& task,
                        const ProgressCallback& progress, std::mutex& mutex, int& done) {
    parallel_for(n, jobs, [&](int i) {
      // The progress call follows the task even when it throws (parallel_for keeps the
      // exception and rethrows the first by index after all tasks).
      struct Report {
        std::mutex& mutex;
        int& done;
        int n;
        const ProgressCallback& progress;
        ~Report() {
          if (!progress) return;
          const std::lock_guard<std::mutex> lock(mutex);
          progress(++done, n);
        }
      } report{mutex, done, n, progress};
      task(i);
    });
  }
};

SerialDistribution& serial() {
  static SerialDistribution instance;
  return instance;
}

Distribution* installed = nullptr;

}  // namespace

void SlotWriter::put(double x) {
  char raw[sizeof x];
  std::memcpy(raw, &x, sizeof x);
  bytes_.append(raw, sizeof raw);
}

void SlotWriter::put_int(std::int64_t x) {
  char raw[sizeof x];
  std::memcpy(raw, &x, sizeof x);
  bytes_.append(raw, sizeof raw);
}

void SlotWriter::put(const std::string& s) {
  put_int(static_cast<std::int64_t>(s.size()));
  bytes_.append(s);
}

void SlotReader::need(std::size_t n) const {
  if (size_ - position_ < n) {
    throw std::runtime_error("distribution: a result slot ends early (codec read/write mismatch)");
  }
}

double SlotReader::get_double() {
  need(sizeof(double));
  double x = 0.0;
  std::memcpy(&x, data_ + position_, sizeof x);
  position_ += sizeof x;
  return x;
}

std::int64_t SlotReader::get_int() {
  need(sizeof(std::int64_t));
  std::int64_t x = 0;
  std::memcpy(&x, data_ + position_, sizeof x);
  position_ += sizeof x;
  return x;
}

std::string SlotReader::get_string() {
  const std::int64_t n = get_int();
  if (n < 0) throw std::runtime_error("distribution: negative string length in a result slot");
  need(static_cast<std::size_t>(n));
  std::string s(data_ + position_, static_cast<std::size_t>(n));
  position_ += static_cast<std::size_t>(n);
  return s;
}

Distribution& distribution() { return installed != nullptr ? *installed : serial(); }

void install_distribution(Distribution* d) { installed = d; }

void distributed_for(int n, int jobs, const std::function<void(int)>& task, const SlotCodec& codec,
                     const ProgressCallback& progress) {
  distribution().run(n, jobs, task, codec, progress);
}

ProgressLine::ProgressLine(std::string label, std::string unit, bool enabled)
    : progress_(std::move(label), 0, std::move(unit), enabled && distribution().is_root()) {}

ProgressCallback ProgressLine::callback(int offset, int study_total) {
  return [this, offset, study_total](int done_here, int total_here) {
    progress_.set_total(study_total > 0 ? study_total : total_here);
    progress_.counter().store(offset + done_here, std::memory_order_relaxed);
  };
}

}  // namespace flexref::studies
