#pragma once
/// \file parallel.hpp
/// Independent integrations on all cores: tasks 0..n−1 on `jobs` threads, each writing its own
/// result slot, so a parallel run gives exactly the numbers of a serial one.
#include <functional>
#include <string>

namespace flexref::studies {

/// Threads for a process: its cores (affinity), and the machine's cores divided among the
/// processes of an MPI run on this machine (studies/mpi/distribution.hpp); at least 1.
int default_jobs();

/// Who runs a study's tasks, for its opening line: "4 threads", or on the ranks of an MPI job
/// (studies/mpi/distribution.hpp) "2 processes x 1 thread each".
std::string workers_text(int jobs);

/// Runs task(i) for i in [0, n) on min(jobs, n) threads; rethrows the first exception (by task
/// index) after all threads have stopped.
void parallel_for(int n, int jobs, const std::function<void(int)>& task);

/// CPU time consumed by the calling thread, in seconds.
double thread_cpu_seconds();

}  // namespace flexref::studies
