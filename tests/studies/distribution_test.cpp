/// Tests of the distribution layer in one process (studies/mpi/distribution.hpp): the slot bytes,
/// distributed_for's slots, progress and failures. tests/studies/mpi/distribution_mpi_test.cpp
/// runs the same contract on two MPI ranks.
#include "studies/mpi/distribution.hpp"

#include <atomic>
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/error.hpp"

namespace flexref::studies {

namespace {

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof x);
  return b;
}

}  // namespace

TEST_CASE("slot bytes: doubles bit for bit, integers, strings, booleans", "[distribution]") {
  const double nan_payload = std::bit_cast<double>(std::uint64_t{0x7ff8000000000abcULL});
  const std::vector<double> doubles{-0.0, 1.0 / 3.0, std::numeric_limits<double>::denorm_min(),
                                    std::numeric_limits<double>::infinity(), nan_payload};
  SlotWriter w;
  for (const double x : doubles) w.put(x);
  w.put(std::numeric_limits<long>::min());
  w.put(std::string("a\0b,\n", 5));
  w.put(true);
  w.put(-7);
  SlotReader r(w.bytes().data(), w.bytes().size());
  for (const double x : doubles) CHECK(bits(r.get_double()) == bits(x));
  CHECK(r.get_int() == std::numeric_limits<long>::min());
  CHECK(r.get_string() == std::string("a\0b,\n", 5));
  CHECK(r.get_bool());
  int i = 0;
  r.get(i);
  CHECK(i == -7);
  CHECK(r.at_end());
  CHECK_THROWS_AS(r.get_double(), std::runtime_error);
}

TEST_CASE("distributed_for in one process: every slot, progress to the end, first failure",
          "[distribution]") {
  REQUIRE(distribution().size() == 1);
  const int n = 23;
  std::vector<double> slots(n, 0.0);
  std::vector<int> progress;
  const SlotCodec codec{[&](int k, SlotWriter& w) { w.put(slots[static_cast<std::size_t>(k)]); },
                        [&](int k, SlotReader& r) { r.get(slots[static_cast<std::size_t>(k)]); }};
  distributed_for(
      n, 3, [&](int k) { slots[static_cast<std::size_t>(k)] = std::sin(k); }, codec,
      [&](int done, int total) {
        CHECK(total == n);
        progress.push_back(done);
      });
  for (int k = 0; k < n; ++k) CHECK(slots[static_cast<std::size_t>(k)] == std::sin(k));
  REQUIRE(progress.size() == static_cast<std::size_t>(n));
  CHECK(progress.back() == n);

  // Tasks 4 (solver) and 9 (bad argument) fail: the one a serial loop meets first is rethrown,
  // with its type, after all tasks ran.
  std::atomic<int> ran = 0;  // the 3 threads count concurrently (a plain int lost increments)
  CHECK_THROWS_AS(distributed_for(
                      n, 3,
                      [&](int k) {
                        ++ran;
                        if (k == 9) throw std::invalid_argument("task 9");
                        if (k == 4) throw core::SolverError("cvode", 1.5, 7, "task 4");
                      },
                      codec),
                  core::SolverError);
  CHECK(ran == n);
}

TEST_CASE("on_root runs the action here and rethrows its failure", "[distribution]") {
  int calls = 0;
  distribution().on_root([&] { ++calls; });
  CHECK(calls == 1);
  CHECK_THROWS_AS(distribution().on_root([] { throw core::InputError("f.toml", 3, "k", "bad"); }),
                  core::InputError);
}

}  // namespace flexref::studies
