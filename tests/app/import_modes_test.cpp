/// `flexref import-modes` on models that CalculiX computes here (docs/calculix.md): a clamped
/// and a free steel bar of 20-node bricks written by examples/calculix/make_deck.py. Needs ccx
/// (Debian calculix-ccx, installed by scripts/setup.sh) and python3; without them each test says
/// so and checks nothing else.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "app/import_modes_command.hpp"
#include "core/error.hpp"
#include "flexible/modal_data.hpp"
#include "scene/calculix_frd.hpp"
#include "scene/calculix_import.hpp"
#include "scene/calculix_input_deck.hpp"
#include "scene/calculix_matrices.hpp"
#include "scene/modal_data_reader.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

// The bar of make_deck.py's defaults: L = 1 m along x from x = 0, b = 0.06 m (y), h = 0.04 m
// (z), steel E = 210 GPa, ν = 0.3, ρ = 7800 kg/m³, 10 × 2 × 2 C3D20R, 10 modes.
constexpr double kL = 1.0;
constexpr double kB = 0.06;
constexpr double kH = 0.04;
constexpr double kE = 2.1e11;
constexpr double kNu = 0.3;
constexpr double kRho = 7800.0;

bool have_tools() {
  return std::system("command -v ccx > /dev/null 2>&1 && command -v python3 > /dev/null 2>&1") == 0;
}

/// A ccx run in a fresh temporary folder: JOB.inp from make_deck.py, then ccx.
struct CcxRun {
  testing::TempDir tmp{"ccx"};
  fs::path dir = tmp.path();
  std::string job;
  explicit CcxRun(const std::string& deck_options) {
    job = (dir / "job").string();
    const std::string command = "python3 examples/calculix/make_deck.py " + deck_options + " -o " +
                                job + ".inp && cd " + dir.string() +
                                " && ccx -i job > ccx.log 2>&1";
    REQUIRE(std::system(command.c_str()) == 0);
  }
  scene::CalculixImport import(const scene::CalculixImportOptions& options = {}) const {
    const scene::CalculixModes frd = scene::read_calculix_frd(job + ".frd");
    const scene::CalculixMatrices matrices = scene::read_calculix_matrices(job);
    const auto dat = scene::read_calculix_dat_eigenvalues(job + ".dat");
    const scene::CalculixDeck deck = scene::read_calculix_deck(job + ".inp");
    return scene::import_calculix_modes(frd, matrices, &dat, options, &deck);
  }
  app::ImportModesOptions command(const std::string& output) const {
    app::ImportModesOptions o;
    o.frd = job + ".frd";
    o.output = (dir / output).string();
    return o;
  }
};

/// Runs the command and requires a core::InputError naming `file` whose message contains
/// `fragment`, and no output file.
void require_refused(const app::ImportModesOptions& options, const std::string& file,
                     const std::string& fragment) {
  try {
    (void)app::import_modes_command(options);
    FAIL("import-modes accepted the input");
  } catch (const core::InputError& e) {
    INFO(e.what());
    CHECK(e.file() == file);
    CHECK_THAT(std::string(e.what()), Contains(fragment));
  }
  CHECK_FALSE(fs::exists(options.output));
}

/// ω_n = (β_n L)² √(EI/(ρA)) / L², Euler–Bernoulli.
double euler_bernoulli(double beta_L, double I) {
  return beta_L * beta_L * std::sqrt(kE * I / (kRho * kB * kH)) / (kL * kL);
}

/// Index of the node nearest to p.
int nearest_node(const flexible::ModalData& data, const Eigen::Vector3d& p) {
  int best = 0;
  for (int k = 1; k < data.node_count(); ++k) {
    if ((data.p_BoNode_B.col(k) - p).norm() < (data.p_BoNode_B.col(best) - p).norm()) best = k;
  }
  return best;
}

/// The bending modes of the written body in a plane: direction a (1: y, 2: z) dominates the
/// displacement of the node at `at`; their frequencies √(K_i/μ_i), ascending.
std::vector<double> bending_frequencies(const flexible::ModalData& data, int a,
                                        const Eigen::Vector3d& at) {
  const int node = nearest_node(data, at);
  const Eigen::MatrixXd m_ff = flexible::modal_mass_matrix(data);
  std::vector<double> out;
  for (int i = 0; i < data.mode_count(); ++i) {
    const Eigen::Vector3d u = data.mode_rows(node).col(i);
    if (std::abs(u(a)) > 0.9 * u.norm()) out.push_back(std::sqrt(data.stiffness(i) / m_ff(i, i)));
  }
  return out;
}

/// Tolerance of a 3D-solid bending frequency against Euler–Bernoulli, mode n (β_n L): shear
/// deformation and rotary inertia lower ω by ½(β_n r)²(1 + E/(κG)) to first order (Timoshenko;
/// r = radius of gyration of the section, κ = 5/6), here allowed twice over, plus 0.5 % for the
/// clamp (it also holds the root's Poisson contraction: +0.43 % measured on mode 1) and the
/// coarse mesh. Two-sided.
double solid_tolerance(double beta_L, double thickness) {
  const double r = thickness / std::sqrt(12.0);
  const double E_over_kappa_G = 2.0 * (1.0 + kNu) / (5.0 / 6.0);
  return std::pow(beta_L * r / kL, 2) * (1.0 + E_over_kappa_G) + 0.005;
}

}  // namespace

TEST_CASE("import-modes: a clamped solid bar against Euler-Bernoulli", "[calculix]") {
  if (!have_tools()) {
    // A required tool missing is a failure, not a pass (scripts/setup.sh installs ccx).
    FAIL("ccx or python3 not found: the CalculiX import cannot be tested");
  }
  const CcxRun run("--boundary clamped");
  app::ImportModesOptions options = run.command("bar.modal.toml");
  REQUIRE(app::import_modes_command(options) == 0);
  const flexible::ModalData data = scene::read_modal_data(options.output);
  REQUIRE(data.mode_count() == 10);
  const Eigen::Vector3d tip(kL, 0.0, 0.0);
  const double beta[2] = {1.87510407, 4.69409113};
  // Bending in z (thickness h: I = b h³/12) and in y (width b: I = h b³/12).
  for (const auto& [a, thickness, I] :
       {std::tuple{2, kH, kB * kH * kH * kH / 12.0}, std::tuple{1, kB, kH * kB * kB * kB / 12.0}}) {
    const std::vector<double> omega = bending_frequencies(data, a, tip);
    REQUIRE(omega.size() >= 2);
    for (int n = 0; n < 2; ++n) {
      const double exact = euler_bernoulli(beta[n], I);
      INFO("plane " << a << ", mode " << n + 1 << ": " << omega[static_cast<std::size_t>(n)]
                    << " vs " << exact);
      CHECK(std::abs(omega[static_cast<std::size_t>(n)] / exact - 1.0) <=
            solid_tolerance(beta[n], thickness));
    }
  }
}

TEST_CASE("import-modes: nodal masses carry the solid's mass, first moment and inertia",
          "[calculix]") {
  if (!have_tools()) {
    // A required tool missing is a failure, not a pass (scripts/setup.sh installs ccx).
    FAIL("ccx or python3 not found: the CalculiX import cannot be tested");
  }
  const CcxRun run("--boundary clamped");
  const scene::CalculixImport result = run.import();
  // The box exactly: m = ρLbh, centre (L/2, 0, 0), inertia about the origin at the root.
  const double m = kRho * kL * kB * kH;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  I(0, 0) = m * (kB * kB + kH * kH) / 12.0;
  I(1, 1) = m * (kL * kL / 3.0 + kH * kH / 12.0);
  I(2, 2) = m * (kL * kL / 3.0 + kB * kB / 12.0);
  // The mesh's coordinates are exact in the .frd's 6 digits and ccx prints M with 14: the nodal
  // sums agree with the box to ~1e-13 (rounding of ~300 terms); 1e-10 leaves room.
  const scene::MassProperties& body = result.body;
  CHECK(body.mass == Approx(m).epsilon(1e-10));
  CHECK((body.centre() - Eigen::Vector3d(kL / 2.0, 0.0, 0.0)).norm() < 1e-10 * kL);
  CHECK((body.I0() - I).norm() < 1e-10 * I.norm());
  // The requirement, checked by the import itself: ≤ 1e-6 against the mass matrix.
  CHECK(result.mass_difference.max() <= 1e-6);
  // The modal masses are matched too, so the frequencies are ccx's (self-check).
  CHECK_THAT(result.mass_model, Contains("diag(m_ff)"));
  CHECK(result.self_check_passed);
  CHECK(result.max_difference < 1e-3);  // 4.4e-4 measured: the off-diagonal of m_ff alone
  CHECK(result.rigid_modes.empty());
}

TEST_CASE("import-modes: a free solid's six rigid-body modes are removed", "[calculix]") {
  if (!have_tools()) {
    // A required tool missing is a failure, not a pass (scripts/setup.sh installs ccx).
    FAIL("ccx or python3 not found: the CalculiX import cannot be tested");
  }
  const CcxRun run("--boundary free --modes 12");
  const scene::CalculixImport result = run.import();
  REQUIRE(result.rigid_modes.size() == 6);
  for (const auto& r : result.rigid_modes) CHECK(r.ccx_mode <= 6);
  REQUIRE(result.modes.size() == 6);
  CHECK(result.modes.front().ccx_mode == 7);
  CHECK(result.self_check_passed);
  // Free-free bending in z against Euler–Bernoulli (β L = 4.7300, 7.8532): the first two z
  // modes are ccx modes 7 and 9 (8 is y bending, b > h).
  const double I = kB * kH * kH * kH / 12.0;
  const std::vector<double> omega =
      bending_frequencies(result.data, 2, Eigen::Vector3d(kL, 0.0, 0.0));
  REQUIRE(omega.size() >= 2);
  const double beta[2] = {4.73004074, 7.85320462};
  for (int n = 0; n < 2; ++n) {
    INFO("mode " << n + 1);
    CHECK(std::abs(omega[static_cast<std::size_t>(n)] / euler_bernoulli(beta[n], I) - 1.0) <=
          solid_tolerance(beta[n], kH));
  }
  // Elastic modes of a free body have no linear momentum: S = Σ m Φ = 0 (matched to rounding
  // when the import reports S among the matched invariants).
  if (result.mass_model.find(", S") != std::string::npos) {
    const Eigen::MatrixXd S =
        scene::nodal_invariants(result.data.mass, result.data.p_BoNode_B, result.data.phi).S;
    CHECK(S.norm() < 1e-9 * std::sqrt(result.solid.mass));
  }
}

TEST_CASE("import-modes: a node subset fails the self-check unless --accept", "[calculix]") {
  if (!have_tools()) {
    // A required tool missing is a failure, not a pass (scripts/setup.sh installs ccx).
    FAIL("ccx or python3 not found: the CalculiX import cannot be tested");
  }
  const CcxRun run("--boundary clamped");
  // The three horizontal layers z = -h/2, 0, h/2 (lattice ids 1-105, 211-315, 421-525): the
  // moments can be matched, the modal masses not; the lumped model is 1-2 % off.
  app::ImportModesOptions options = run.command("subset.modal.toml");
  options.nodes = "1-105,211-315,421-525";
  require_refused(options, options.frd, "self-check failed");
  options.accept = true;
  REQUIRE(app::import_modes_command(options) == 0);
  const flexible::ModalData data = scene::read_modal_data(options.output);
  CHECK(data.node_count() == 255);
  std::ifstream in(options.output);
  std::stringstream text;
  text << in.rdbuf();
  CHECK_THAT(text.str(), Contains("# self-check failure ACCEPTED"));
  CHECK_THAT(text.str(), Contains("# frequency self-check"));

  SECTION("a coplanar node set cannot carry the inertia") {
    options.accept = false;
    options.nodes.clear();
    options.node_set = "TIP";
    options.output = (run.dir / "tip.modal.toml").string();
    require_refused(options, run.job + ".mas", "one plane");
  }
}

TEST_CASE("import-modes: bad CalculiX output is refused with its file and line, nothing written",
          "[calculix]") {
  if (!have_tools()) {
    // A required tool missing is a failure, not a pass (scripts/setup.sh installs ccx).
    FAIL("ccx or python3 not found: the CalculiX import cannot be tested");
  }
  const CcxRun run("--boundary clamped");
  app::ImportModesOptions options = run.command("bad.modal.toml");
  const auto read = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  SECTION("truncated .frd") {
    const std::string frd = read(options.frd);
    std::ofstream(options.frd) << frd.substr(0, frd.size() * 2 / 3);
    require_refused(options, options.frd, "truncated");
  }
  SECTION("wrong mode count: the .dat lists a mode the .frd lacks") {
    std::string dat = read(run.job + ".dat");
    const std::size_t row = dat.find("     10   ");
    REQUIRE(row != std::string::npos);
    dat.insert(dat.find('\n', row) + 1,
               "     11   0.2000000E+09   0.1414214E+05   0.2250791E+04   0.0000000E+00\n");
    std::ofstream(run.job + ".dat") << dat;
    require_refused(options, options.frd, "wrong mode count");
  }
  SECTION("wrong mode count: more modes selected than the step has") {
    options.modes = "1-12";
    require_refused(options, options.frd, "wrong mode count");
  }
  SECTION("missing mass data") {
    fs::remove(run.job + ".mas");
    require_refused(options, run.job + ".mas", "SOLVER=MATRIXSTORAGE");
  }
  SECTION("matrices of another model") {
    const CcxRun other("--boundary clamped --density 2700 --young 7e10");
    options.matrices = other.job;
    require_refused(options, options.frd, "different models");
  }
  SECTION("matrices of another mesh") {
    const CcxRun other("--boundary clamped --nx 6");
    options.matrices = other.job;
    require_refused(options, other.job + ".dof", "different meshes");
  }
}

TEST_CASE("import-modes: the element families users write, clamped and free", "[calculix]") {
  if (!have_tools()) {
    // A required tool missing is a failure, not a pass (scripts/setup.sh installs ccx).
    FAIL("ccx or python3 not found: the CalculiX import cannot be tested");
  }
  // The bar of make_deck.py's defaults in each family: solids with incompatible modes (C3D8I:
  // three internal nodes per element), 20-node bricks, shells (expanded by ccx into C3D20R and
  // C3D8I bricks through the thickness) and beams (expanded around the rectangular section).
  // C3D8I 20 x 2 x 2 is the deck that was refused ("node 190 is not a node of bar.frd").
  const struct {
    const char* element;
    const char* mesh;
  } families[] = {{"C3D8I", "--nx 20 --ny 2 --nz 2"},
                  {"C3D20R", "--nx 10 --ny 2 --nz 2"},
                  {"S8R", "--nx 10 --ny 2"},
                  {"S4", "--nx 20 --ny 2"},
                  {"B32R", "--nx 10"},
                  {"B31", "--nx 20"}};
  for (const auto& family : families) {
    // Clamped: six elastic modes; free: ten modes, the six rigid-body modes and four elastic
    // ones (with six, the free beams' nodal masses match only m, s0, J0 and their frequencies
    // are 1.8e-2 (B31) and 4.6e-2 (B32R) off: docs/calculix.md).
    for (const std::string boundary : {"clamped", "free"}) {
      INFO(family.element << " " << boundary);
      const CcxRun run(std::string("--element ") + family.element + " " + family.mesh +
                       " --boundary " + boundary +
                       (boundary == "clamped" ? " --modes 6" : " --modes 10"));
      app::ImportModesOptions options = run.command("bar.modal.toml");
      REQUIRE(app::import_modes_command(options) == 0);
      const scene::CalculixImport result = run.import();
      // The body's frequencies are ccx's within the self-check's tolerance (the command wrote
      // the file without --accept, so they are; said here for every family).
      CHECK(result.self_check_passed);
      CHECK(result.max_difference <= scene::kDefaultFrequencyTolerance);
      CHECK(result.rigid_modes.size() == (boundary == "free" ? 6u : 0u));
      // Every family is the same box of steel: m = ρLbh, centre (L/2, 0, 0), the box's inertia
      // about the root. The (expanded) nodes' coordinates are exact in the .frd's 6 digits and
      // ccx prints M with 14: the projections agree with the box to ~1e-13; 1e-10 leaves room.
      const double m = kRho * kL * kB * kH;
      Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
      I(0, 0) = m * (kB * kB + kH * kH) / 12.0;
      I(1, 1) = m * (kL * kL / 3.0 + kH * kH / 12.0);
      I(2, 2) = m * (kL * kL / 3.0 + kB * kB / 12.0);
      CHECK(std::abs(result.solid.mass / m - 1.0) < 1e-10);
      CHECK((result.solid.centre() - Eigen::Vector3d(kL / 2.0, 0.0, 0.0)).norm() < 1e-10 * kL);
      CHECK((result.solid.I0() - I).norm() < 1e-10 * I.norm());
      CHECK(result.mass_difference.max() <= scene::kMassPropertyTolerance);
      // The deck's node on the tip's axis is a node of the body under its own number, where
      // the deck puts it (a shell or beam node is added back; its expansion keeps "n<id>-<k>").
      const flexible::ModalData data = scene::read_modal_data(options.output);
      const scene::CalculixDeck deck = scene::read_calculix_deck(run.job + ".inp");
      int tip = 0;
      for (const auto& [id, p] : deck.nodes) {
        if ((p - Eigen::Vector3d(kL, 0.0, 0.0)).norm() < 1e-12) tip = id;
      }
      REQUIRE(tip > 0);
      const auto named =
          std::find(data.node_names.begin(), data.node_names.end(), "n" + std::to_string(tip));
      REQUIRE(named != data.node_names.end());
      // The .frd's 6 digits: positions agree to 5e-6 of their size (1 m).
      CHECK((data.p_BoNode_B.col(named - data.node_names.begin()) - Eigen::Vector3d(kL, 0.0, 0.0))
                .norm() < 1e-5);
    }
  }
}

}  // namespace flexref
