/// \file input_files_test.cpp
/// Every reader of a user's file refuses what is not a regular file (io/input_file.hpp): given
/// a FIFO, each throws core::InputError naming the path, at once, instead of waiting for a
/// writer or reading for ever.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "scene/calculix_frd.hpp"
#include "scene/calculix_input_deck.hpp"
#include "scene/calculix_matrices.hpp"
#include "scene/modal_data_reader.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/temp_dir.hpp"
#include "trajectory/reference_sidecar.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

/// This test's own folder (tests/support/temp_dir.hpp).
using InputFilesTempDir = testing::TempDir;

/// The message of the core::InputError that `read` throws on a FIFO at `fifo` ("" when it
/// throws none). A writer thread feeds the FIFO `text`, so that a reader that opens it anyway
/// reads that text and ends instead of hanging the test; a writer still waiting afterwards (the
/// reader refused without opening) is released by a reader opened here.
std::string message_on_fifo(const fs::path& fifo, const std::string& text,
                            const std::function<void(const std::string&)>& read) {
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::thread writer([&] {
    const int fd = ::open(fifo.c_str(), O_WRONLY);
    if (fd < 0) return;
    const ssize_t written = ::write(fd, text.data(), text.size());
    (void)written;
    ::close(fd);
  });
  std::string message;
  try {
    read(fifo.string());
  } catch (const core::InputError& e) {
    message = e.what();
  }
  const int release = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  writer.join();
  if (release >= 0) ::close(release);
  fs::remove(fifo);
  return message;
}

TEST_CASE("every reader refuses a FIFO at once, naming it", "[scene][io]") {
  InputFilesTempDir tmp;
  const fs::path fifo = tmp.path() / "input";
  const std::string scene =
      "[scene]\nname = \"x\"\nend_time = 1.0\noutput_step = 0.1\n[[body]]\nname = \"b\"\n"
      "mass = 1.0\ninertia = [1.0, 2.0, 3.0]\n";
  const std::string csv = "t,b.x\n0,0\n";
  const std::vector<std::pair<std::string, std::function<void(const std::string&)>>> readers = {
      {"read_scene", [](const std::string& p) { (void)scene::read_scene(p); }},
      {"read_modal_data", [](const std::string& p) { (void)scene::read_modal_data(p); }},
      {"read_calculix_frd", [](const std::string& p) { (void)scene::read_calculix_frd(p); }},
      {"read_calculix_dat_eigenvalues",
       [](const std::string& p) { (void)scene::read_calculix_dat_eigenvalues(p); }},
      {"read_calculix_dofs",
       [](const std::string& p) {
         std::vector<int> node, direction;
         scene::read_calculix_dofs(p, node, direction);
       }},
      {"read_calculix_matrix",
       [](const std::string& p) { (void)scene::read_calculix_matrix(p, 3); }},
      {"read_calculix_node_set",
       [](const std::string& p) { (void)scene::read_calculix_node_set(p, "ROOT"); }},
      {"read_csv", [](const std::string& p) { (void)trajectory::read_csv(p); }},
      {"read_run_csv", [](const std::string& p) { (void)trajectory::read_run_csv(p); }},
  };
  for (const auto& [name, read] : readers) {
    INFO(name);
    const std::string message = message_on_fifo(fifo, name == "read_scene" ? scene : csv, read);
    CHECK_THAT(message, Contains(fifo.string()) && Contains("FIFO"));
  }
  // A sidecar that is a FIFO (beside a regular CSV).
  std::ofstream(tmp.path() / "run.csv") << csv;
  const std::string message =
      message_on_fifo(tmp.path() / "run.csv.meta.toml", "[integrator]\n", [&](const std::string&) {
        (void)trajectory::read_reference_sidecar((tmp.path() / "run.csv").string());
      });
  CHECK_THAT(message, Contains("run.csv.meta.toml") && Contains("FIFO"));
}

}  // namespace
}  // namespace flexref
