/// \file scene_fuzz_test.cpp
/// The scene reader never crashes: mutants of every bundled scene either read into a model or
/// are rejected with a core::InputError that names the file and a line; no other exception
/// escapes. Mutations: systematic (every line deleted, every number replaced by each hostile
/// value) and random (fixed-seed std::mt19937: byte replacement, insertion and deletion, line
/// deletion, duplication and swaps, value replacement and type swaps, 1 to 3 per mutant).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::app {
namespace {

constexpr std::array<std::string_view, 15> kScenes = {"free_spin",
                                                      "book_toss",
                                                      "book_toss_step",
                                                      "coulomb_wall",
                                                      "heavy_top",
                                                      "pendulum",
                                                      "flexible_spinner",
                                                      "rotating_cantilever",
                                                      "spin_up_beam",
                                                      "bouncing_ball",
                                                      "sliding_block",
                                                      "top_on_plane",
                                                      "tippe_top",
                                                      "pendulum_on_sliding_support",
                                                      "double_pendulum_impacts"};

// Replacements for a value: non-finite, huge, tiny, wrong types, wrong shapes.
constexpr std::array<std::string_view, 18> kHostileValues = {
    "0",     "-1",     "1e308",       "nan",       "inf",       "-inf",
    "\"x\"", "[]",     "{}",          "true",      "1e-320",    "-0.0",
    "1e400", "[1, 2]", "[[1, 2, 3]]", "[1, 2, 3]", "{ a = 1 }", "99999999999999999999"};

// Bytes inserted or substituted: mostly TOML punctuation and value characters, so that
// mutants reach the reader's checks rather than stopping at the first syntax error.
constexpr std::string_view kSyntaxBytes = " =[]{},.\"'#\n0123456789-+_eEinfatrux";

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

/// [begin, end) of every number-like token outside comments and strings.
std::vector<std::pair<std::size_t, std::size_t>> number_tokens(const std::string& text) {
  std::vector<std::pair<std::size_t, std::size_t>> tokens;
  bool comment = false;
  bool string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') comment = string = false;
    if (comment) continue;
    if (c == '"') string = !string;
    if (string) continue;
    if (c == '#') {
      comment = true;
      continue;
    }
    const bool starts = (c >= '0' && c <= '9') || ((c == '-' || c == '+') && i + 1 < text.size() &&
                                                   text[i + 1] >= '0' && text[i + 1] <= '9');
    const bool after_word =
        i > 0 && (std::isalnum(static_cast<unsigned char>(text[i - 1])) != 0 || text[i - 1] == '_');
    if (!starts || after_word) continue;
    std::size_t j = i + 1;
    while (j < text.size() &&
           std::string_view("0123456789.eE+-_").find(text[j]) != std::string_view::npos) {
      ++j;
    }
    tokens.emplace_back(i, j);
    i = j - 1;
  }
  return tokens;
}

class Mutator {
 public:
  explicit Mutator(std::uint32_t seed) : rng_(seed) {}

  std::string mutate(std::string text) {
    const std::size_t count = 1 + index(3);
    for (std::size_t k = 0; k < count; ++k) text = mutate_once(std::move(text));
    return text;
  }

 private:
  std::size_t index(std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
  }
  char random_byte() {
    if (index(2) == 0) return kSyntaxBytes[index(kSyntaxBytes.size())];
    return static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng_));
  }

  std::string mutate_once(std::string text) {
    if (text.empty()) return std::string(1, random_byte());
    std::vector<std::string> lines = split_lines(text);
    switch (index(9)) {
      case 0:  // byte replacement
        text[index(text.size())] = random_byte();
        return text;
      case 1:  // byte insertion
        text.insert(index(text.size() + 1), 1, random_byte());
        return text;
      case 2:  // byte deletion
        text.erase(index(text.size()), 1);
        return text;
      case 3:  // line deletion
        if (!lines.empty())
          lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(index(lines.size())));
        return join_lines(lines);
      case 4: {  // line duplication
        if (lines.empty()) return text;
        const std::size_t i = index(lines.size());
        lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), lines[i]);
        return join_lines(lines);
      }
      case 5:  // line swap
        if (lines.size() > 1) std::swap(lines[index(lines.size())], lines[index(lines.size())]);
        return join_lines(lines);
      case 6:
      case 7: {  // number replaced by a hostile value
        const auto tokens = number_tokens(text);
        if (tokens.empty()) return text;
        const auto [begin, end] = tokens[index(tokens.size())];
        text.replace(begin, end - begin, kHostileValues[index(kHostileValues.size())]);
        return text;
      }
      default: {  // type swap: a whole value after '=' replaced by one of another type
        const std::size_t i = index(lines.size());
        const std::size_t eq = lines[i].find(" = ");
        if (eq == std::string::npos) return text;
        lines[i] =
            lines[i].substr(0, eq + 3) + std::string(kHostileValues[index(kHostileValues.size())]);
        return join_lines(lines);
      }
    }
  }

  std::mt19937 rng_;
};

/// Outcome counts and the first mutant that broke the contract.
struct FuzzTally {
  int parsed = 0;
  int rejected = 0;
  int escaped = 0;
  std::string first_escape;

  void run(const std::string& text, const std::string& file) {
    const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
    std::string broken;
    try {
      const scene::Scene scene = scene::parse_scene(text, file);
      if (scene.model == nullptr || scene.model->num_bodies() < 1 || !(scene.end_time > 0.0) ||
          !(scene.output_step > 0.0) || scene.output_step > scene.end_time) {
        broken = "accepted an invalid scene";
      }
      for (const core::Body& b : scene.model ? scene.model->bodies() : std::vector<core::Body>{}) {
        if (!b.I_Br_B_inverse().allFinite()) broken = "accepted a body with an unusable inertia";
      }
      ++parsed;
    } catch (const core::InputError& e) {
      ++rejected;
      // Every error of a scene text names the file and a line inside (or just past) it.
      if (e.file() != file || e.line() < 1 || e.line() > lines + 1) {
        broken = std::string("InputError without a usable location: ") + e.what();
      }
    } catch (const std::exception& e) {
      broken = std::string("escaped std::exception: ") + e.what();
    } catch (...) {
      broken = "escaped a non-standard exception";
    }
    if (!broken.empty()) {
      ++escaped;
      if (first_escape.empty()) first_escape = broken + "\n--- mutant:\n" + text;
    }
  }
};

}  // namespace

TEST_CASE("mutated bundled scenes never crash the reader", "[app][scene][fuzz]") {
  FuzzTally tally;
  int mutants = 0;
  for (std::size_t s = 0; s < kScenes.size(); ++s) {
    const std::string file = "scenes/" + std::string(kScenes[s]) + ".toml";
    const std::string original = read_text(file);
    REQUIRE_FALSE(original.empty());

    // Systematic: each line deleted, each number replaced by each hostile value.
    const std::vector<std::string> lines = split_lines(original);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      std::vector<std::string> shorter = lines;
      shorter.erase(shorter.begin() + static_cast<std::ptrdiff_t>(i));
      tally.run(join_lines(shorter), file);
      ++mutants;
    }
    for (const auto& [begin, end] : number_tokens(original)) {
      for (const std::string_view value : kHostileValues) {
        std::string text = original;
        text.replace(begin, end - begin, value);
        tally.run(text, file);
        ++mutants;
      }
    }

    // Random: a fixed seed per scene so that a failure reproduces.
    Mutator mutator(static_cast<std::uint32_t>(20240601 + s));
    for (int k = 0; k < 400; ++k) {
      tally.run(mutator.mutate(original), file);
      ++mutants;
    }
  }
  INFO("first failure: " << tally.first_escape);
  REQUIRE(tally.escaped == 0);
  CHECK(tally.parsed + tally.rejected == mutants);
  // Both outcomes are exercised (mutants that stay valid, e.g. a changed initial velocity,
  // and mutants that are rejected).
  CHECK(mutants > 2000);
  CHECK(tally.parsed > 100);
  CHECK(tally.rejected > 1000);
}

TEST_CASE("hostile texts are rejected, not crashed on", "[app][scene][fuzz]") {
  const std::vector<std::string> texts = {
      "",
      std::string(1, '\0'),
      "\xef\xbb\xbf[scene]",
      "[scene]\nname = \"\xff\xfe\"",
      "a = " + std::string(50000, '['),
      "a = " + std::string(50000, '{') + "b = 1",
      std::string(50000, 'a') + " = 1",
      [] {
        std::string key = "a";
        for (int i = 0; i < 20000; ++i) key += ".a";
        return key + " = 1";
      }(),
      "[" + std::string(20000, '.') + "]",
      "a = \"\"\"" + std::string(1000, '"'),
      "a = '''\n''''''",
      "[[body]]\n[body]",
      std::string("[scene]\nname = \"t\"\nend_time = 1\noutput_step = 1\n") +
          "[[body]]\nname = \"b\"\nmass = 1\ninertia = [1, 1, 1]\norientation = [0, 0, 0, "
          "1e-200]\n",
  };
  for (const std::string& text : texts) {
    FuzzTally tally;
    tally.run(text, "hostile.toml");
    INFO(tally.first_escape);
    CHECK(tally.escaped == 0);
  }
}

}  // namespace flexref::app
