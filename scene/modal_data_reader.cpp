#include "scene/modal_data_reader.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "io/input_file.hpp"
#include "io/output_file.hpp"
#include "scene/scene_toml.hpp"

namespace flexref::scene {
namespace {

using scene_toml::Sign;
using scene_toml::Table;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The shortest decimal form that reads back as the same double (std::to_chars), always with a
// '.' or an exponent so that TOML reads a float.
std::string format_number(double x) {
  std::array<char, 64> buffer{};
  const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x);
  if (ec != std::errc()) throw std::invalid_argument("cannot format a number");
  std::string s(buffer.data(), end);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

// A TOML basic string: quotes, backslashes and control characters escaped.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20 || u == 0x7f) {
      constexpr std::string_view kHex = "0123456789ABCDEF";
      out += "\\u00";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    } else {
      out += c;
    }
  }
  return out + "\"";
}

bool writable_name(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

void read_nodes(const Table& root, flexible::ModalData& data) {
  const std::vector<Table> nodes =
      root.tables("nodes", "an array of nodes { name, mass, position }");
  if (nodes.empty()) {
    root.fail("nodes",
              "required key is missing or empty; expected an array of nodes "
              "{ name = \"...\", mass = <kg>, position = [x, y, z] }");
  }
  const auto N = static_cast<Eigen::Index>(nodes.size());
  data.mass.resize(N);
  data.p_BoNode_B.resize(3, N);
  const bool named = nodes.front().has("name");
  std::unordered_map<std::string, int> lines;  // name → line of its first use
  for (Eigen::Index k = 0; k < N; ++k) {
    const Table& node = nodes[static_cast<std::size_t>(k)];
    node.check_keys({"name", "mass", "position"});
    if (node.has("name") != named) {
      node.fail_table(std::string("give every node a name or none (") +
                      (named ? "nodes[1] has one" : "nodes[1] has none") + ")");
    }
    if (named) {
      std::string name = node.name("name", "a node name");
      const auto [it, inserted] = lines.emplace(name, node.line_of("name"));
      if (!inserted) {
        node.fail("name", "duplicate node name \"" + name + "\" (first used at line " +
                              std::to_string(it->second) + ")");
      }
      data.node_names.push_back(std::move(name));
    }
    data.mass(k) = node.number("mass", Sign::kPositive, "the node's mass in kg, > 0");
    data.p_BoNode_B.col(k) =
        node.vector3("position", "the undeformed position [x, y, z] in m, body frame");
  }
}

// Reads `shape` of one mode into column i of data.phi.
void read_shape(const Table& mode, flexible::ModalData& data, Eigen::Index i) {
  const int N = data.node_count();
  const std::string rows_expected = "an array of " + std::to_string(N) +
                                    " rows [ux, uy, uz] (one per node, in the order of `nodes`)";
  const toml::value* shape = mode.find("shape");
  if (shape == nullptr) mode.fail("shape", "required key is missing; expected " + rows_expected);
  if (!shape->is_array()) {
    mode.fail("shape", "expected " + rows_expected + ", got " + scene_toml::describe(*shape));
  }
  const toml::array& rows = shape->as_array();
  if (rows.size() != static_cast<std::size_t>(N)) {
    mode.fail("shape", "expected " + rows_expected + ", got " + std::to_string(rows.size()) +
                           (rows.size() == 1 ? " row" : " rows"));
  }
  for (int k = 0; k < N; ++k) {
    const toml::value& row = rows[static_cast<std::size_t>(k)];
    const std::string key = "shape[" + std::to_string(k + 1) + "]";
    if (!row.is_array() || row.as_array().size() != 3) {
      mode.fail_at(row, key,
                   "expected the displacement [ux, uy, uz] of node " + std::to_string(k + 1) +
                       ", got " + scene_toml::describe(row));
    }
    for (int a = 0; a < 3; ++a) {
      data.phi(3 * k + a, i) =
          mode.to_number(row.as_array()[static_cast<std::size_t>(a)], key, Sign::kAny,
                         "a finite displacement in m per unit modal coordinate");
    }
  }
}

void read_modes(const Table& root, double tolerance, flexible::ModalData& data) {
  const std::vector<Table> modes = root.tables("mode", "[[mode]] tables");
  if (modes.empty()) root.fail("mode", "no [[mode]] table; at least one mode is required");
  const auto n = static_cast<Eigen::Index>(modes.size());
  const int N = data.node_count();
  data.phi = Eigen::MatrixXd::Zero(3 * Eigen::Index{N}, n);
  data.stiffness.resize(n);
  data.damping_ratio.resize(n);
  const bool named = modes.front().has("name");
  for (Eigen::Index i = 0; i < n; ++i) {
    const Table& mode = modes[static_cast<std::size_t>(i)];
    mode.check_keys(
        {"name", "stiffness", "omega", "frequency_hz", "modal_mass", "damping_ratio", "shape"});
    if (mode.has("name") != named) {
      mode.fail_table(std::string("give every mode a name or none (") +
                      (named ? "mode[1] has one" : "mode[1] has none") + ")");
    }
    if (named) data.mode_names.push_back(mode.name("name", "a mode name"));
    read_shape(mode, data, i);
    // μ_i = Σ m_k |Φ_k,i|², the diagonal of m_ff that the model uses.
    double mu = 0.0;
    for (int k = 0; k < N; ++k) mu += data.mass(k) * data.mode_rows(k).col(i).squaredNorm();
    if (!(mu > 0.0)) mode.fail("shape", "the mode has no displacement at any node");
    if (mode.has("modal_mass")) {
      const double given = mode.number("modal_mass", Sign::kPositive,
                                       "the modal mass Σ m_k |Φ_k|² (> 0), as a check");
      const double difference = std::abs(given - mu) / mu;
      if (difference > tolerance) {
        std::ostringstream what;
        what.precision(6);
        what << "modal_mass = " << given << " but the nodal masses and this shape give "
             << "Σ m_k |Φ_k|² = " << mu << " (relative difference " << difference
             << " > modal_mass_tolerance = " << tolerance
             << "); check the units and the normalization of the shape, or omit modal_mass";
        mode.fail("modal_mass", what.str());
      }
    }
    const std::vector<std::string_view> given_keys = [&] {
      std::vector<std::string_view> keys;
      for (const std::string_view key : {"stiffness", "omega", "frequency_hz"}) {
        if (mode.has(key)) keys.push_back(key);
      }
      return keys;
    }();
    if (given_keys.empty()) {
      mode.fail_table(
          "one of stiffness (modal stiffness), omega (rad/s) or frequency_hz (Hz) is required");
    }
    if (given_keys.size() > 1) {
      mode.fail(given_keys[1], "give only one of stiffness, omega and frequency_hz (" +
                                   std::string(given_keys[0]) + " is given too)");
    }
    const std::string_view key = given_keys.front();
    if (key == "stiffness") {
      data.stiffness(i) = mode.number(key, Sign::kNonNegative, "the modal stiffness K_i ≥ 0");
    } else {
      const double omega =
          key == "omega"
              ? mode.number(key, Sign::kNonNegative, "the natural frequency in rad/s, ≥ 0")
              : kTwoPi * mode.number(key, Sign::kNonNegative, "the natural frequency in Hz, ≥ 0");
      data.stiffness(i) = omega * omega * mu;  // K_i = μ_i ω_i²
      if (!std::isfinite(data.stiffness(i))) {
        mode.fail(key, "the stiffness ω² Σ m_k |Φ_k|² overflows");
      }
    }
    data.damping_ratio(i) =
        mode.number_or("damping_ratio", 0.0, Sign::kNonNegative, "a damping ratio ζ ≥ 0");
  }
  const int dependent = flexible::first_dependent_mode(flexible::modal_mass_matrix(data));
  if (dependent >= 0) {
    modes[static_cast<std::size_t>(dependent)].fail_table(
        "the mode is (numerically) a linear combination of the modes before it: the modal "
        "mass matrix Σ m_k Φ_kᵀ Φ_k is not positive definite");
  }
}

// The twelve unit-load matrices of [geometric_stiffness] (flexible/geometric_stiffness.hpp):
// keys E_x, E_y, E_z, then F_ab in the order 3a+b.
constexpr std::array<std::string_view, 12> kGeometricKeys = {
    "E_x", "E_y", "E_z", "F_xx", "F_xy", "F_xz", "F_yx", "F_yy", "F_yz", "F_zx", "F_zy", "F_zz"};

Eigen::MatrixXd& geometric_matrix(flexible::GeometricStiffness& g, std::size_t key) {
  return key < 3 ? g.E[key] : g.F[key - 3];
}

// [geometric_stiffness]: any subset of the twelve n×n matrices (absent ones are zero), each an
// array of n rows of n numbers, symmetric.
void read_geometric_stiffness(const Table& root, flexible::ModalData& data) {
  const std::optional<Table> table = root.table(
      "geometric_stiffness",
      "a table [geometric_stiffness] of n×n matrices E_x … F_zz (docs/geometric_stiffening.md)");
  if (!table) return;
  const Table& g = *table;
  g.check_keys({kGeometricKeys[0], kGeometricKeys[1], kGeometricKeys[2], kGeometricKeys[3],
                kGeometricKeys[4], kGeometricKeys[5], kGeometricKeys[6], kGeometricKeys[7],
                kGeometricKeys[8], kGeometricKeys[9], kGeometricKeys[10], kGeometricKeys[11]});
  const Eigen::Index n = data.mode_count();
  const std::string expected = "an array of " + std::to_string(n) + " rows of " +
                               std::to_string(n) + " numbers (one row and column per mode)";
  flexible::GeometricStiffness out;
  for (std::size_t key = 0; key < kGeometricKeys.size(); ++key) {
    geometric_matrix(out, key) = Eigen::MatrixXd::Zero(n, n);
  }
  bool any = false;
  for (std::size_t key = 0; key < kGeometricKeys.size(); ++key) {
    const std::string_view name = kGeometricKeys[key];
    const toml::value* v = g.find(name);
    if (v == nullptr) continue;
    any = true;
    if (!v->is_array() || static_cast<Eigen::Index>(v->as_array().size()) != n) {
      g.fail(name, "expected " + expected + ", got " + scene_toml::describe(*v));
    }
    Eigen::MatrixXd& M = geometric_matrix(out, key);
    for (Eigen::Index i = 0; i < n; ++i) {
      const toml::value& row = v->as_array()[static_cast<std::size_t>(i)];
      const std::string row_key = std::string(name) + "[" + std::to_string(i + 1) + "]";
      if (!row.is_array() || static_cast<Eigen::Index>(row.as_array().size()) != n) {
        g.fail_at(row, row_key,
                  "expected a row of " + std::to_string(n) + " numbers, got " +
                      scene_toml::describe(row));
      }
      for (Eigen::Index j = 0; j < n; ++j) {
        M(i, j) = g.to_number(row.as_array()[static_cast<std::size_t>(j)], row_key, Sign::kAny,
                              "a finite number");
      }
    }
    // Symmetric to 1e-10 of the largest entry (the Lagrangian needs symmetric matrices; a file
    // written with 17 digits from a symmetric matrix passes, a transposed block does not).
    const double scale = M.cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = 0; j < i; ++j) {
        if (std::abs(M(i, j) - M(j, i)) > 1e-10 * scale) {
          g.fail(name, "the matrix is not symmetric: entry (" + std::to_string(i + 1) + ", " +
                           std::to_string(j + 1) + ") is " + format_number(M(i, j)) + ", (" +
                           std::to_string(j + 1) + ", " + std::to_string(i + 1) + ") is " +
                           format_number(M(j, i)));
        }
      }
    }
  }
  if (!any) g.fail_table("no matrix given; expected at least one of E_x, E_y, E_z, F_xx … F_zz");
  data.geometric = std::move(out);
}

flexible::ModalData read_document(const toml::value& document, const std::string& file) {
  const Table root(document, file, "");
  root.check_keys({"format", "version", "description", "modal_mass_tolerance", "nodes", "mode",
                   "geometric_stiffness"});
  const std::string format = root.string("format", "\"" + std::string(kModalDataFormat) + "\"");
  if (format != kModalDataFormat) {
    root.fail("format", "expected \"" + std::string(kModalDataFormat) + "\", got \"" + format +
                            "\" (is this a modal-data file?)");
  }
  const double version = root.number("version", Sign::kPositive, "the format version 1");
  if (version != 1.0) {
    root.fail("version", "unsupported version " + scene_toml::describe(*root.find("version")) +
                             "; this flexref reads version 1");
  }
  (void)root.optional_string("description", "a string");
  const double tolerance = root.number_or("modal_mass_tolerance", kDefaultModalMassTolerance,
                                          Sign::kPositive, "a relative tolerance > 0");
  flexible::ModalData data;
  read_nodes(root, data);
  read_modes(root, tolerance, data);
  read_geometric_stiffness(root, data);
  try {
    data.validate();  // everything is checked above, with lines; kept as a safety net
  } catch (const std::invalid_argument& e) {
    throw core::InputError(file, 0, "", e.what());
  }
  return data;
}

}  // namespace

flexible::ModalData parse_modal_data(const std::string& text, const std::string& file_name) {
  try {
    const toml::value document = scene_toml::parse(text, file_name);
    return read_document(document, file_name);
  } catch (const core::InputError&) {
    throw;
  } catch (const toml::exception& e) {
    // Not expected (every access is type-checked first): keep toml11's line.
    throw core::InputError(file_name, static_cast<int>(e.location().line()), "", e.what());
  } catch (const std::exception& e) {
    throw core::InputError(file_name, 0, "",
                           std::string("cannot read the modal data: ") + e.what());
  }
}

flexible::ModalData read_modal_data(const std::string& path) {
  std::string text;
  try {
    io::InputFile in(path, "the modal-data file (TOML)");
    if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
    text = in.read_all();
  } catch (const core::InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw core::InputError(path, 0, "",
                           std::string("cannot read the modal-data file: ") + e.what());
  }
  return parse_modal_data(text, path);
}

std::string format_modal_data(const flexible::ModalData& data, const std::string& description) {
  data.validate();
  for (const auto* names : {&data.node_names, &data.mode_names}) {
    for (const std::string& name : *names) {
      if (!writable_name(name)) {
        throw std::invalid_argument("modal data: the name \"" + name +
                                    "\" cannot be written (use ASCII letters, digits, '_' and "
                                    "'-')");
      }
    }
  }
  const Eigen::MatrixXd m_ff = flexible::modal_mass_matrix(data);
  std::ostringstream out;
  out << "# flexref modal data (docs/modal_data.md). SI units; positions and displacements in\n"
      << "# the body frame.\n"
      << "format = " << quoted(kModalDataFormat) << "\n"
      << "version = 1\n";
  if (!description.empty()) out << "description = " << quoted(description) << "\n";
  out << "\n# " << data.node_count() << " nodes: mass (kg), undeformed position (m)\n"
      << "nodes = [\n";
  for (int k = 0; k < data.node_count(); ++k) {
    out << "  { ";
    if (!data.node_names.empty()) {
      out << "name = " << quoted(data.node_names[static_cast<std::size_t>(k)]) << ", ";
    }
    const Eigen::Vector3d x = data.p_BoNode_B.col(k);
    out << "mass = " << format_number(data.mass(k)) << ", position = [" << format_number(x.x())
        << ", " << format_number(x.y()) << ", " << format_number(x.z()) << "] },\n";
  }
  out << "]\n";
  for (int i = 0; i < data.mode_count(); ++i) {
    const double mu = m_ff(i, i);
    const double omega = std::sqrt(data.stiffness(i) / mu);
    out << "\n[[mode]]\n";
    if (!data.mode_names.empty()) {
      out << "name = " << quoted(data.mode_names[static_cast<std::size_t>(i)]) << "\n";
    }
    out << "stiffness = " << format_number(data.stiffness(i))
        << "  # omega = " << format_number(omega) << " rad/s, " << format_number(omega / kTwoPi)
        << " Hz\n"
        << "modal_mass = " << format_number(mu) << "\n"
        << "damping_ratio = " << format_number(data.damping_ratio(i)) << "\n"
        << "shape = [\n";
    for (int k = 0; k < data.node_count(); ++k) {
      const auto u = data.mode_rows(k).col(i);
      out << "  [" << format_number(u(0)) << ", " << format_number(u(1)) << ", "
          << format_number(u(2)) << "],\n";
    }
    out << "]\n";
  }
  if (data.geometric) {
    out << "\n# Geometric stiffening: unit-load matrices about the frame origin "
           "(docs/geometric_stiffening.md)\n[geometric_stiffness]\n";
    flexible::GeometricStiffness g = *data.geometric;
    for (std::size_t key = 0; key < kGeometricKeys.size(); ++key) {
      const Eigen::MatrixXd& M = geometric_matrix(g, key);
      if (M.cwiseAbs().maxCoeff() == 0.0) continue;
      out << kGeometricKeys[key] << " = [\n";
      for (Eigen::Index i = 0; i < M.rows(); ++i) {
        out << "  [";
        for (Eigen::Index j = 0; j < M.cols(); ++j) {
          out << (j > 0 ? ", " : "") << format_number(M(i, j));
        }
        out << "],\n";
      }
      out << "]\n";
    }
  }
  return out.str();
}

void write_modal_data(const flexible::ModalData& data, const std::string& path,
                      const std::string& description) {
  io::write_output_file(path, format_modal_data(data, description));
}

}  // namespace flexref::scene
