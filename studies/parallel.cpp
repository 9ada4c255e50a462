#include "studies/parallel.hpp"

#include <sched.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

#include "studies/mpi/distribution.hpp"

namespace flexref::studies {

int default_jobs() {
  // The cores this process may run on (an MPI launcher may bind it to one), and the machine's
  // cores shared by the processes of the run on this machine.
  int cores = static_cast<int>(std::thread::hardware_concurrency());
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) cores = std::min(cores, CPU_COUNT(&set));
  const int shared =
      static_cast<int>(std::thread::hardware_concurrency()) / distribution().processes_on_node();
  return std::max(1, std::min(cores, shared));
}

std::string workers_text(int jobs) {
  const auto threads = [](int n) { return std::to_string(n) + (n == 1 ? " thread" : " threads"); };
  const int processes = distribution().size();
  if (processes <= 1) return threads(jobs);
  return std::to_string(processes) + " processes x " + threads(jobs) + " each";
}

void parallel_for(int n, int jobs, const std::function<void(int)>& task) {
  if (n <= 0) return;
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  std::atomic<int> next{0};
  auto worker = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        task(i);
      } catch (...) {
        errors[static_cast<std::size_t>(i)] = std::current_exception();
      }
    }
  };
  const int threads = std::clamp(jobs, 1, n);
  if (threads == 1) {
    worker();
  } else {
    std::vector<std::jthread> pool;
    pool.reserve(static_cast<std::size_t>(threads));
    for (int k = 0; k < threads; ++k) pool.emplace_back(worker);
  }
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace flexref::studies
