/// Tests of the CalculiX readers (scene/calculix_frd.hpp, scene/calculix_matrices.hpp,
/// scene/calculix_input_deck.hpp) and of the nodal mass lumping (scene/nodal_mass_lumping.hpp)
/// on synthetic input, written here in ccx's fixed formats: these run without CalculiX.
/// tests/app/import_modes_test.cpp runs ccx itself.
#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "scene/calculix_frd.hpp"
#include "scene/calculix_import.hpp"
#include "scene/calculix_input_deck.hpp"
#include "scene/calculix_matrices.hpp"
#include "scene/index_ranges.hpp"
#include "scene/nodal_mass_lumping.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

std::string node_line(int id, double x, double y, double z) {
  char line[128];
  std::snprintf(line, sizeof line, " -1%10d%12.5E%12.5E%12.5E", id, x, y, z);
  return line;
}

/// A .frd of three nodes and two modes (numbered `first` and `second`), as ccx writes it (long
/// format).
std::string tiny_frd(int first = 1, int second = 2) {
  std::ostringstream f;
  f << "    1C\n    1UUSER\n";
  f << "    2C                             3                                     1\n";
  f << node_line(1, 0.0, 0.0, 0.0) << "\n"
    << node_line(2, 0.5, 0.0, 0.0) << "\n"
    << node_line(7, 1.0, -0.25, 1.5e-3) << "\n -3\n";
  f << "    3C                             1                                     1\n"
    << " -1         1    1    0    1\n -2         1         2         7\n -3\n";
  for (int m = 1; m <= 2; ++m) {
    const int number = m == 1 ? first : second;
    f << "    1PSTEP                         " << m << "           1           1\n";
    f << "    1PGK                " << (m == 1 ? "4.475604E+04" : "1.001517E+05") << "\n";
    f << "    1PMODE                         " << number << "\n";
    char header[128];
    std::snprintf(header, sizeof header,
                  "  100CL  %3d%12.8f%12d                     2%5dMODAL      1", 100 + m,
                  m == 1 ? 33.67021894 : 50.36738146, 3, number);
    f << header << "\n -4  DISP        4    1\n -5  D1          1    2    1    0\n"
      << " -5  D2          1    2    2    0\n -5  D3          1    2    3    0\n"
      << " -5  ALL         1    2    0    0    1ALL\n";
    f << node_line(1, 0.0, 0.0, 0.0) << "\n"
      << node_line(7, 1.0 * m, -2.5e-1, 3.0e-3) << "\n"
      << node_line(2, 0.5 * m, -1.25e-1, 1.0e-4) << "\n -3\n";
  }
  f << " 9999\n";
  return f.str();
}

scene::CalculixModes parse_frd(const std::string& text) {
  std::istringstream in(text);
  return scene::parse_calculix_frd(in, "job.frd");
}

/// Requires a core::InputError from parse_frd(text) at `line` whose message contains `fragment`.
void require_frd_error(const std::string& text, int line, const std::string& fragment) {
  try {
    (void)parse_frd(text);
  } catch (const core::InputError& e) {
    INFO(e.what());
    CHECK(e.file() == "job.frd");
    CHECK(e.line() == line);
    CHECK_THAT(std::string(e.what()), Contains(fragment));
    return;
  }
  FAIL("the .frd reader accepted bad input");
}

/// Line number (from 1) of the first line of `text` starting with `prefix`.
int line_of(const std::string& text, const std::string& prefix, int occurrence = 1) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (line.rfind(prefix, 0) == 0 && --occurrence == 0) return n;
  }
  return -1;
}

int line_count(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

using testing::TempDir;

}  // namespace

TEST_CASE("frd reader: nodes, eigenvalues, frequencies and shapes in ccx's fixed columns",
          "[calculix]") {
  const scene::CalculixModes modes = parse_frd(tiny_frd());
  REQUIRE(modes.node_ids == std::vector<int>{1, 2, 7});
  CHECK(modes.positions(0, 2) == 1.0);
  CHECK(modes.positions(1, 2) == -0.25);
  CHECK(modes.positions(2, 2) == 1.5e-3);
  REQUIRE(modes.steps.size() == 1);
  REQUIRE(modes.steps[0].modes.size() == 2);
  const scene::CalculixMode& m2 = modes.steps[0].modes[1];
  CHECK(m2.number == 2);
  CHECK(m2.eigenvalue == 1.001517e5);
  CHECK(m2.frequency_hz == 50.36738146);
  // Records in another order than the node block land at their node.
  CHECK(m2.shape(0, 2) == 2.0);     // node 7
  CHECK(m2.shape(0, 1) == 1.0);     // node 2
  CHECK(m2.shape(2, 1) == 1.0e-4);  // node 2, z
  CHECK(m2.line == line_of(tiny_frd(), "  100C", 2));
}

TEST_CASE("frd reader: truncated, inconsistent or foreign files are errors with their line",
          "[calculix]") {
  const std::string good = tiny_frd();
  SECTION("no end record") {
    const std::string text = good.substr(0, good.find(" 9999"));
    require_frd_error(text, line_of(good, " 9999") - 1, "truncated");
  }
  SECTION("cut inside a displacement block") {
    const std::string text = good.substr(0, good.find(node_line(2, 1.0, -0.125, 1.0e-4)));
    require_frd_error(text, line_count(text), "truncated");
  }
  SECTION("a mode missing from the sequence") {
    const std::string text = tiny_frd(1, 3);
    require_frd_error(text, line_of(text, "  100C", 2), "mode 2 was expected");
  }
  SECTION("a node in a mode that the mesh lacks") {
    std::string text = good;
    text.replace(text.find(node_line(7, 1.0, -0.25, 3.0e-3)), 13, " -1         9");
    require_frd_error(text, line_of(text, " -1         9"), "node 9");
  }
  SECTION("a malformed number") {
    std::string text = good;
    text.replace(text.find("5.00000E-01"), 11, "5.00O00E-01");
    require_frd_error(text, line_of(good, node_line(2, 0.5, 0.0, 0.0)), "expected a number");
  }
  SECTION("binary blocks") {
    std::string text = good;
    const std::size_t at = text.find("    2C");
    text.replace(text.find('\n', at) - 1, 1, "2");
    require_frd_error(text, line_of(good, "    2C"), "binary");
  }
  SECTION("no modes") {
    const std::string text = good.substr(0, good.find("    1PSTEP")) + " 9999\n";
    require_frd_error(text, line_of(text, " 9999"), "no mode shapes");
  }
}

TEST_CASE("dat reader: eigenvalue tables per frequency step", "[calculix]") {
  const std::string table =
      "\n     E I G E N V A L U E   O U T P U T\n\n MODE NO    EIGENVALUE    "
      "                   FREQUENCY   \n                                     REAL PART      "
      "      IMAGINARY PART\n                           (RAD/TIME)      (CYCLES/TIME     "
      "(RAD/TIME)\n\n      1   0.4475604E+05   0.2115562E+03   0.3367022E+02   0.0000000E+00\n"
      "      2   0.1001517E+06   0.3164676E+03   0.5036738E+02   0.0000000E+00\n\n"
      "     P A R T I C I P A T I O N   F A C T O R S\n";
  std::istringstream in(table + table);
  const auto tables = scene::parse_calculix_dat_eigenvalues(in, "job.dat");
  REQUIRE(tables.size() == 2);
  CHECK(tables[1].eigenvalues == std::vector<double>{0.4475604e5, 0.1001517e6});
  CHECK(tables[0].line == 2);
}

TEST_CASE("matrix reader: .dof, .mas and .sti, missing files name the deck keyword", "[calculix]") {
  TempDir dir;
  dir.write("job.dof", "1.1\n1.2\n1.3\n7.1\n7.2\n7.3\n");
  dir.write("job.mas", "1 1  2.0000000000000e+00\n1 4  5.0000000000000e-01\n4 4 2.0e+00\n");
  dir.write("job.sti", "2 2  3.0e+00\n");
  const std::string base = (dir.path() / "job").string();
  const scene::CalculixMatrices m = scene::read_calculix_matrices(base);
  CHECK(m.dof_node == std::vector<int>{1, 1, 1, 7, 7, 7});
  CHECK(m.dof_direction == std::vector<int>{0, 1, 2, 0, 1, 2});
  CHECK(m.mass.coeff(3, 0) == 0.5);  // the lower triangle is filled in
  CHECK(m.mass.coeff(0, 3) == 0.5);
  CHECK(m.stiffness.coeff(1, 1) == 3.0);

  SECTION("missing mass data") {
    fs::remove(dir.path() / "job.mas");
    try {
      (void)scene::read_calculix_matrices(base);
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.file() == base + ".mas");
      CHECK_THAT(std::string(e.what()), Contains("SOLVER=MATRIXSTORAGE"));
    }
  }
  SECTION("an entry outside the degrees of freedom") {
    dir.write("job.mas", "1 1 1.0\n1 9 1.0\n");
    try {
      (void)scene::read_calculix_matrices(base);
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.line() == 2);
      CHECK_THAT(std::string(e.what()), Contains("outside the 6 degrees of freedom"));
    }
  }
  SECTION("an entry given twice") {
    dir.write("job.mas", "1 2 1.0\n2 1 1.0\n");
    CHECK_THROWS_WITH(scene::read_calculix_matrices(base), Contains("given twice"));
  }
  SECTION("a rotational degree of freedom") {
    dir.write("job.dof", "1.1\n1.5\n");
    CHECK_THROWS_WITH(scene::read_calculix_matrices(base), Contains("only displacements 1-3"));
  }
}

TEST_CASE("input deck: node sets with GENERATE, set references, *NODE NSET and *INCLUDE",
          "[calculix]") {
  TempDir dir;
  dir.write("mesh.inp", "*NODE, NSET=Nall\n1, 0, 0, 0\n2, 1, 0, 0\n3, 2, 0, 0\n");
  const std::string deck =
      dir.write("job.inp",
                "** comment\n*INCLUDE, INPUT=mesh.inp\n*NSET, NSET=a, GENERATE\n10, 16, 3\n"
                "*nset,nset=B\n5, A,\n2\n");
  CHECK(scene::read_calculix_node_set(deck, "b") == std::vector<int>{2, 5, 10, 13, 16});
  CHECK(scene::read_calculix_node_set(deck, "NALL") == std::vector<int>{1, 2, 3});
  CHECK_THROWS_WITH(scene::read_calculix_node_set(deck, "TIP"), Contains("node sets: A, B, NALL"));
}

TEST_CASE("selections: ranges and single numbers", "[calculix]") {
  CHECK(scene::parse_index_list("7,1-3,2", "--modes") == std::vector<int>{1, 2, 3, 7});
  CHECK(scene::parse_ranges("4-6,9", "--nodes") ==
        std::vector<std::pair<int, int>>{{4, 6}, {9, 9}});
  for (const char* bad : {"", "0", "3-1", "a", "1,,2", "-2", "1-"}) {
    INFO(bad);
    CHECK_THROWS_WITH(scene::parse_index_list(bad, "--modes"), Contains("--modes"));
  }
}

TEST_CASE("nodal lumping: the moments of a solid are reproduced to rounding", "[calculix]") {
  // Random nodes in a box and random positive masses as the initial guess; the target is
  // another random distribution on the same nodes (so a solution exists).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  const int n = 60;
  Eigen::Matrix3Xd x(3, n);
  Eigen::VectorXd initial(n), other(n);
  for (int k = 0; k < n; ++k) {
    x.col(k) << 2.0 * u(rng) + 10.0, 0.3 * u(rng), 0.1 * u(rng) - 0.5;
    initial(k) = u(rng);
    other(k) = u(rng);
  }
  const scene::MassProperties target = scene::nodal_mass_properties(other, x);
  const Eigen::VectorXd m = scene::moment_matched_masses(initial, x, target);
  const scene::MassPropertyDifference d =
      scene::relative_difference(target, scene::nodal_mass_properties(m, x));
  // The 10×10 system in centred, scaled coordinates, refined once: rounding, a few ε.
  CHECK(d.max() < 1e-13);
  CHECK(m.minCoeff() > 0.0);
  // The change is the smallest relative one: moving to `other` itself is not (it changes more).
  CHECK((m - initial).cwiseQuotient(initial).norm() <=
        (other - initial).cwiseQuotient(initial).norm());

  SECTION("coplanar nodes cannot carry a solid's second moments") {
    Eigen::Matrix3Xd flat = x;
    flat.row(2).setConstant(0.25);
    CHECK_THROWS_WITH(scene::moment_matched_masses(initial, flat, target), Contains("one plane"));
  }
  SECTION("with modal invariants: S, X and diag(m_ff) of random shapes") {
    // Shapes uniform in [−1, 1] from the test's seeded generator (not Eigen's Random, which
    // draws from std::rand's unseeded global state).
    std::uniform_real_distribution<double> shape(-1.0, 1.0);
    const Eigen::MatrixXd phi = Eigen::MatrixXd::NullaryExpr(3 * n, 2, [&] { return shape(rng); });
    const scene::LinearInvariants wanted = scene::nodal_invariants(other, x, phi);
    scene::InvariantSelection selection;
    selection.first_moment = true;
    selection.position_moment = true;
    const Eigen::VectorXd mi = scene::invariant_matched_masses(initial, x, phi, wanted, selection);
    const scene::InvariantDifference di =
        scene::relative_difference(wanted, scene::nodal_invariants(mi, x, phi));
    CHECK(di.rigid.max() < 1e-12);
    CHECK(di.S < 1e-12);
    CHECK(di.X < 1e-12);
    // diag(m_ff) matched; its off-diagonal is not a constraint.
    CHECK(std::abs(scene::nodal_invariants(mi, x, phi).m_ff(1, 1) - wanted.m_ff(1, 1)) <
          1e-12 * wanted.m_ff.trace());
  }
}

TEST_CASE("scalar mass matrix: M0 of M0 ⊗ I₃ and the anisotropy of anything else", "[calculix]") {
  Eigen::MatrixXd M0(2, 2);
  M0 << 2.0, 0.5, 0.5, 1.0;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6, 6);
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j)
      M.block<3, 3>(3 * i, 3 * j) = M0(i, j) * Eigen::Matrix3d::Identity();
  }
  double anisotropy = 1.0;
  const Eigen::SparseMatrix<double> S0 = scene::scalar_mass_matrix(M.sparseView(), anisotropy);
  CHECK(anisotropy == 0.0);
  // The blocks' diagonal is M0's entries exactly (copied, not computed).
  CHECK(Eigen::MatrixXd(S0) == M0);
  M(1, 4) += 0.1;  // a direction coupling
  M(4, 1) += 0.1;
  (void)scene::scalar_mass_matrix(M.sparseView(), anisotropy);
  // Tolerance: the coupling over the diagonal entries of the matrix written: a quotient of sums
  // of O(1) entries, a few roundings of O(1)-relative operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14
  // leaves a factor ~10 over them.
  CHECK(anisotropy == Approx(0.1 / 2.0).epsilon(1e-14));
}

}  // namespace flexref
