/// The distribution contract (studies/mpi/distribution.hpp) on the processes of an MPI job: run by
/// ctest as `mpirun -np 2 studies_distribution_mpi_test` and once without a launcher (one
/// process). Every process runs the same test cases in the same order, so their collective
/// steps match; each checks what it sees.
#define CATCH_CONFIG_RUNNER
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "studies/mpi/distribution.hpp"

using namespace flexref;
using namespace flexref::studies;

namespace {

struct Slot {
  double value = 0.0;
  int rank = -1;  ///< the process that ran the task
  std::string text;
};

SlotCodec codec(std::vector<Slot>& slots) {
  return {[&slots](int k, SlotWriter& w) {
            const Slot& s = slots[static_cast<std::size_t>(k)];
            w.put(s.value);
            w.put(s.rank);
            w.put(s.text);
          },
          [&slots](int k, SlotReader& r) {
            Slot& s = slots[static_cast<std::size_t>(k)];
            r.get(s.value);
            r.get(s.rank);
            r.get(s.text);
          }};
}

}  // namespace

TEST_CASE("every task runs once on some process and every process gets every slot",
          "[distribution][mpi]") {
  const Distribution& d = distribution();
  const int n = 41;
  std::vector<Slot> slots(n);
  std::atomic<int> ran_here{0};
  std::vector<int> progress;
  distributed_for(
      n, 2,
      [&](int k) {
        ++ran_here;
        // Uneven costs, as in a study: later tasks take longer.
        std::this_thread::sleep_for(std::chrono::milliseconds(2 + k % 7));
        slots[static_cast<std::size_t>(k)] = {std::exp(0.1 * k) / 3.0, d.rank(),
                                              "task " + std::to_string(k)};
      },
      codec(slots),
      [&](int done, int total) {
        CHECK(total == n);
        progress.push_back(done);
      });
  int mine = 0;
  std::vector<int> per_rank(static_cast<std::size_t>(d.size()), 0);
  for (int k = 0; k < n; ++k) {
    const Slot& s = slots[static_cast<std::size_t>(k)];
    CHECK(s.value == std::exp(0.1 * k) / 3.0);  // bit for bit: the same operation everywhere
    CHECK(s.text == "task " + std::to_string(k));
    REQUIRE(s.rank >= 0);
    REQUIRE(s.rank < d.size());
    ++per_rank[static_cast<std::size_t>(s.rank)];
    if (s.rank == d.rank()) ++mine;
  }
  CHECK(mine == ran_here.load());
  for (const int count : per_rank) CHECK(count > 0);  // dynamic scheduling fed every process
  if (d.is_root()) {
    REQUIRE_FALSE(progress.empty());
    CHECK(progress.back() == n);
  } else {
    CHECK(progress.empty());  // progress is the root's
  }
}

TEST_CASE("the first failing task's exception reaches every process", "[distribution][mpi]") {
  const int n = 20;
  std::vector<Slot> slots(n);
  try {
    distributed_for(
        n, 1,
        [&](int k) {
          std::this_thread::sleep_for(std::chrono::milliseconds(3));
          if (k == 13) throw std::invalid_argument("task 13 is bad");
          if (k == 6) throw core::SolverError("ida", 0.25, 12, "task 6 failed");
        },
        codec(slots));
    FAIL("no exception");
  } catch (const core::SolverError& e) {
    CHECK(std::string(e.what()) == "ida failed at t = 0.25 (step 12): task 6 failed");
    CHECK(e.time() == 0.25);
    CHECK(e.step() == 12);
  }
  CHECK(distribution().failure_is_collective());
}

TEST_CASE("on_root: the root's failure is every process's", "[distribution][mpi]") {
  int calls = 0;
  distribution().on_root([&] { ++calls; });
  CHECK(calls == (distribution().is_root() ? 1 : 0));
  try {
    distribution().on_root([] { throw core::InputError("out", 4, "key", "cannot write"); });
    FAIL("no exception");
  } catch (const core::InputError& e) {
    CHECK(e.file() == "out");
    CHECK(e.line() == 4);
    CHECK(std::string(e.what()) == "out:4: key 'key': cannot write");
  }
}

int main(int argc, char** argv) {
  ProcessSession session(argc, argv);
  // Ranks other than 0 have their standard output silenced: a failure seen by rank 0 alone is
  // printed; to see another rank's, run it with `-o file`.
  const int failed = Catch::Session().run(argc, argv);
  return session.finish(failed == 0 ? 0 : 1);
}
