/// The reference sidecar (REF.csv.meta.toml) read back by compare: what `flexref reference`
/// writes — including the +inf of an estimate without a usable check — is read as written, and
/// a sidecar that could make a comparison look certified when it is not is refused naming the
/// file and key.
#include "trajectory/reference_sidecar.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref::trajectory {
namespace {

using Catch::Matchers::Contains;

/// This program's folder for the sidecars (removed at exit).
const testing::TempDir& sidecar_dir() {
  static const testing::TempDir dir("sidecar");
  return dir;
}

/// Writes `meta` as the sidecar of a CSV path in sidecar_dir() and returns the CSV path.
std::string with_sidecar(const std::string& name, const std::string& meta) {
  const std::string csv = (sidecar_dir() / (name + ".csv")).string();
  std::ofstream(csv + ".meta.toml") << meta;
  return csv;
}

TEST_CASE("sidecar: a missing file is not an error, the estimate is then unknown", "[sidecar]") {
  const std::string csv = (sidecar_dir() / "none.csv").string();
  const ReferenceSidecar s = read_reference_sidecar(csv);
  CHECK_FALSE(s.found);
  CHECK_FALSE(s.has_estimate);
}

TEST_CASE("sidecar: integrator and estimate are read as flexref reference writes them",
          "[sidecar]") {
  const std::string csv = with_sidecar("full", R"([integrator]
solver = "cvode"
rtol = 1e-10
[error_estimate]
metric = "rotation+points"
estimate = 3.5e-11
method = "2 x largest distance to a more accurate solution"
energy_balance = 2.4e-5
energy_estimate = 4.8e-5
[[error_estimate.check]]
role = "tighter"
)");
  const ReferenceSidecar s = read_reference_sidecar(csv);
  CHECK(s.found);
  CHECK(s.has_estimate);
  CHECK(s.solver == "cvode");
  CHECK(s.rtol == 1e-10);
  CHECK(s.metric == "rotation+points");
  CHECK(s.estimate == 3.5e-11);
  CHECK(s.estimate_method == "2 x largest distance to a more accurate solution");
  CHECK(s.energy_balance == 2.4e-5);
  CHECK(s.energy_estimate == 4.8e-5);
  // The factor 100 (reference contributes ≤ 1 %): exactly at the bound is certified, below not.
  CHECK(is_certified(kCertificationFactor * s.estimate, s.estimate));
  CHECK(is_certified(3.6e-9, s.estimate));
  CHECK_FALSE(is_certified(3.4e-9, s.estimate));
}

TEST_CASE("sidecar: an unknown (inf) estimate is read and certifies nothing", "[sidecar]") {
  const std::string csv = with_sidecar("inf", R"([error_estimate]
metric = "rotation+points"
estimate = inf
method = "no usable check"
)");
  const ReferenceSidecar s = read_reference_sidecar(csv);
  REQUIRE(s.has_estimate);
  CHECK(std::isinf(s.estimate));
  CHECK_FALSE(is_certified(1.0e6, s.estimate));
}

TEST_CASE("sidecar: estimates that could fool a comparison are refused naming file and key",
          "[sidecar]") {
  const auto refused = [](const std::string& name, const std::string& meta,
                          const std::string& key) {
    const std::string csv = with_sidecar(name, meta);
    CHECK_THROWS_WITH(read_reference_sidecar(csv), Contains(csv + ".meta.toml") && Contains(key));
  };
  refused("nan", "[error_estimate]\nmetric = \"rotation\"\nestimate = nan\n",
          "error_estimate.estimate");
  refused("negative", "[error_estimate]\nmetric = \"rotation\"\nestimate = -1e-9\n",
          "error_estimate.estimate");
  refused("string", "[error_estimate]\nmetric = \"rotation\"\nestimate = \"small\"\n",
          "error_estimate.estimate");
  refused("no_metric", "[error_estimate]\nestimate = 1e-9\n", "error_estimate.metric");
  refused("balance",
          "[error_estimate]\nmetric = \"rotation\"\nestimate = 1e-9\nenergy_balance = \"x\"\n",
          "error_estimate.energy_balance");
  refused("not_table", "error_estimate = 1e-9\n", "error_estimate");
  CHECK_THROWS_AS(read_reference_sidecar(with_sidecar("broken", "[error_estimate\n")),
                  core::InputError);
}

TEST_CASE("sidecar: found beside the file a link points to, where flexref writes it", "[sidecar]") {
  namespace fs = std::filesystem;
  const testing::TempDir tmp("sidecar-link");
  const fs::path& dir = tmp.path();
  fs::create_directories(dir / "data");
  std::ofstream(dir / "data" / "ref.csv") << "t\n0\n";
  std::ofstream(dir / "data" / "ref.csv.meta.toml") << "[integrator]\nsolver = \"cvode\"\n";
  fs::create_symlink("data/ref.csv", dir / "link.csv");
  const ReferenceSidecar s = read_reference_sidecar((dir / "link.csv").string());
  CHECK(s.found);
  CHECK(s.solver == "cvode");
  CHECK(fs::equivalent(s.path, dir / "data" / "ref.csv.meta.toml"));
  // Beside the name given when the target has none (a sidecar copied by hand).
  fs::remove(dir / "data" / "ref.csv.meta.toml");
  std::ofstream(dir / "link.csv.meta.toml") << "[integrator]\nsolver = \"ida\"\n";
  CHECK(read_reference_sidecar((dir / "link.csv").string()).solver == "ida");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace flexref::trajectory
