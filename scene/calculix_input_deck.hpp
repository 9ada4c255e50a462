#pragma once
/// \file calculix_input_deck.hpp
/// Node sets of a CalculiX input deck (JOB.inp), for `flexref import-modes --node-set`: the
/// .frd holds no sets. Reads `*NSET, NSET=name [, GENERATE]` (data lines of node numbers and
/// names of sets defined before, or "first, last, increment" with GENERATE), the sets named by
/// `*NODE, NSET=name`, and follows `*INCLUDE, INPUT=file` (relative to the including file).
/// Keywords and set names are case-insensitive, as in ccx; `**` starts a comment line.
#include <string>
#include <vector>

namespace flexref::scene {

/// The node numbers of set `name` in the deck at `path`, sorted, without repeats. Throws
/// core::InputError naming the file and line of a malformed line, or the deck when the set is
/// not defined (listing the sets that are).
std::vector<int> read_calculix_node_set(const std::string& path, const std::string& name);

}  // namespace flexref::scene
