#include "scene/calculix_input_deck.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <map>
#include <sstream>
#include <utility>

#include "core/error.hpp"
#include "io/input_file.hpp"

namespace flexref::scene {
namespace {

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string part; std::getline(in, part, ',');) out.push_back(trim(part));
  return out;
}

/// The value of parameter `key` (upper case) of a keyword line, or "" when absent.
std::string parameter(const std::vector<std::string>& fields, const std::string& key) {
  for (std::size_t i = 1; i < fields.size(); ++i) {
    const std::size_t eq = fields[i].find('=');
    if (eq == std::string::npos) continue;
    if (upper(trim(fields[i].substr(0, eq))) == key) return trim(fields[i].substr(eq + 1));
  }
  return "";
}

bool has_flag(const std::vector<std::string>& fields, const std::string& key) {
  for (std::size_t i = 1; i < fields.size(); ++i) {
    if (upper(fields[i]) == key) return true;
  }
  return false;
}

bool integer(const std::string& s, int& value) {
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return !s.empty() && ec == std::errc() && p == s.data() + s.size();
}

bool real(const std::string& s, double& value) {
  if (s.empty()) {
    value = 0.0;  // ccx reads a blank coordinate as 0
    return true;
  }
  const char* begin = s.data() + (s.front() == '+' ? 1 : 0);  // from_chars takes no '+'
  const auto [p, ec] = std::from_chars(begin, s.data() + s.size(), value);
  return ec == std::errc() && p == s.data() + s.size();
}

class DeckReader {
 public:
  CalculixDeck deck;

  void read(const std::string& path, int depth) {
    if (depth > 20) throw core::InputError(path, 0, "", "*INCLUDE nested more than 20 deep");
    io::InputFile in(path, "a CalculiX input deck (.inp)");
    if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
    enum class Block { kNone, kNode, kNset, kGenerate, kBoundary };
    Block block = Block::kNone;
    std::string set;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      const std::string text = trim(line);
      if (text.empty() || text.starts_with("**")) continue;
      const std::vector<std::string> fields = split(text);
      if (text.front() == '*') {
        const std::string keyword = upper(fields[0]);
        block = Block::kNone;
        if (keyword == "*INCLUDE") {
          const std::string file = parameter(fields, "INPUT");
          if (file.empty()) throw core::InputError(path, number, "", "*INCLUDE without INPUT=");
          read((std::filesystem::path(path).parent_path() / file).string(), depth + 1);
        } else if (keyword == "*NODE") {
          set = upper(parameter(fields, "NSET"));
          block = Block::kNode;
        } else if (keyword == "*NSET") {
          set = upper(parameter(fields, "NSET"));
          if (set.empty()) throw core::InputError(path, number, "", "*NSET without NSET=");
          deck.sets[set];
          block = has_flag(fields, "GENERATE") ? Block::kGenerate : Block::kNset;
        } else if (keyword == "*BOUNDARY") {
          block = Block::kBoundary;
        }
        continue;
      }
      if (block == Block::kNode) {
        int id = 0;
        if (!integer(fields[0], id)) {
          throw core::InputError(path, number, "",
                                 "expected a node number, got \"" + fields[0] + "\"");
        }
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for (std::size_t a = 0; a < 3 && a + 1 < fields.size(); ++a) {
          if (!real(fields[a + 1], x(static_cast<Eigen::Index>(a)))) {
            throw core::InputError(path, number, "",
                                   "node " + std::to_string(id) + ": coordinate \"" +
                                       fields[a + 1] + "\" is not a number");
          }
        }
        deck.nodes[id] = x;
        if (!set.empty()) deck.sets[set].push_back(id);
      } else if (block == Block::kNset) {
        for (const std::string& f : fields) {
          if (!f.empty()) add_nodes(path, number, f, deck.sets[set]);
        }
      } else if (block == Block::kGenerate) {
        int first = 0;
        int last = 0;
        int step = 1;
        if (fields.size() < 2 || !integer(fields[0], first) || !integer(fields[1], last) ||
            (fields.size() > 2 && !fields[2].empty() && !integer(fields[2], step)) || step < 1 ||
            last < first) {
          throw core::InputError(path, number, "",
                                 "expected \"first, last[, increment]\" of *NSET, GENERATE");
        }
        for (int id = first; id <= last; id += step) deck.sets[set].push_back(id);
      } else if (block == Block::kBoundary) {
        int first = 0;
        int last = 0;
        if (fields.size() < 2 || !integer(fields[1], first) ||
            (fields.size() > 2 && !fields[2].empty() && !integer(fields[2], last))) {
          throw core::InputError(path, number, "",
                                 "expected \"node or set, first direction[, last direction[, "
                                 "value]]\" of *BOUNDARY");
        }
        if (last == 0) last = first;
        if (first < 1 || last < first) {
          throw core::InputError(path, number, "",
                                 "*BOUNDARY directions " + std::to_string(first) + "-" +
                                     std::to_string(last) + ": expected first <= last, from 1");
        }
        std::vector<int> held;
        add_nodes(path, number, fields[0], held);
        unsigned mask = 0;
        // Directions above 6 (temperature 11, …) hold no displacement.
        for (int d = first; d <= std::min(last, 6); ++d) mask |= 1u << (d - 1);
        for (const int id : held) deck.boundary[id] |= mask;
      }
    }
  }

 private:
  /// A node number, or the nodes of a set defined before, appended to `out`.
  void add_nodes(const std::string& path, int line, const std::string& field,
                 std::vector<int>& out) const {
    int id = 0;
    if (integer(field, id)) {
      out.push_back(id);
      return;
    }
    const auto it = deck.sets.find(upper(field));
    if (it == deck.sets.end()) {
      throw core::InputError(path, line, "",
                             "\"" + field + "\" is neither a node number nor a set defined before");
    }
    const std::vector<int> copy = it->second;
    out.insert(out.end(), copy.begin(), copy.end());
  }
};

}  // namespace

CalculixDeck read_calculix_deck(const std::string& path) {
  DeckReader reader;
  reader.deck.file = path;
  reader.read(path, 0);
  return std::move(reader.deck);
}

std::vector<int> read_calculix_node_set(const std::string& path, const std::string& name) {
  const CalculixDeck deck = read_calculix_deck(path);
  const auto it = deck.sets.find(upper(name));
  if (it == deck.sets.end() || it->second.empty()) {
    std::string known;
    for (const auto& [set, nodes] : deck.sets) known += (known.empty() ? "" : ", ") + set;
    throw core::InputError(path, 0, "",
                           "no node set \"" + name + "\" in the deck (node sets: " +
                               (known.empty() ? std::string("none") : known) + ")");
  }
  std::vector<int> nodes = it->second;
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace flexref::scene
