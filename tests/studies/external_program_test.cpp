/// Running another code's integrator (studies/external_program.hpp): the substituted command,
/// its exit status, output tail, CPU time and timeout, and the file it writes read under the
/// trajectory contract.
#include "studies/external_program.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/error.hpp"

namespace flexref::studies {
namespace {

using Catch::Matchers::Contains;

TEST_CASE("the command template: {dt} with 17 digits, paths quoted only when needed",
          "[studies][external]") {
  CHECK(substitute_command("prog {scene} {dt} {output}", "/a/b.toml", 0.1, "/o/x.csv") ==
        "prog /a/b.toml 0.10000000000000001 /o/x.csv");
  CHECK(substitute_command("p {dt} {output}", "", 0.0025, "/my dir/it's.csv") ==
        "p 0.0025000000000000001 '/my dir/it'\\''s.csv'");
  CHECK_THROWS_WITH(substitute_command("p {scene} {output}", "s", 0.1, "o"),
                    Contains("must contain {dt} and {output}"));
  CHECK_THROWS_WITH(substitute_command("p {step} {dt} {output}", "s", 0.1, "o"),
                    Contains("unknown placeholder '{step}'"));
}

TEST_CASE("a program's exit status, signal, output tail, CPU time and timeout",
          "[studies][external]") {
  const ProgramOutcome ok = run_program("echo hello; echo world >&2; exit 0", 0.0);
  CHECK(ok.exit_status == 0);
  CHECK(ok.signal == 0);
  CHECK(ok.output_tail == "hello\nworld");
  const ProgramOutcome failed = run_program("echo boom >&2; exit 3", 0.0);
  CHECK(failed.exit_status == 3);
  CHECK(failed.output_tail == "boom");
  const ProgramOutcome killed = run_program("kill -9 $$", 0.0);
  CHECK(killed.signal == 9);
  // A busy loop of ~0.2 s of CPU in a child of the shell: wait4 counts the grandchild's time
  // (the shell waited for it). 0.05 s is a quarter of the work, safe on a loaded machine.
  const ProgramOutcome busy = run_program(
      "/usr/bin/python3 -c 'import time\nt = time.process_time()\n"
      "while time.process_time() - t < 0.2: pass'; true",
      0.0);
  CHECK(busy.exit_status == 0);
  CHECK(busy.cpu_seconds >= 0.05);
  // The timeout kills the whole process group (the shell and its sleep).
  const ProgramOutcome slow = run_program("sleep 20; echo never", 0.2);
  CHECK(slow.timed_out);
  CHECK(slow.signal == 9);
  CHECK(slow.output_tail.empty());
}

TEST_CASE("a level: failures say why, the file is read under the contract", "[studies][external]") {
  const std::string out =
      (std::filesystem::temp_directory_path() / "flexref_ext_level.csv").string();
  ExternalCommand command;
  command.scene = "scene.toml";
  command.command = "printf 't,body.W1\\n0,1\\n' > {output}; : {dt}";
  const ExternalLevel level = run_external_level(command, 0.1, out);
  CHECK(level.run.table.columns == std::vector<std::string>{"t", "body.W1"});
  CHECK(level.run.source == out);
  command.command = "echo 'cannot converge' >&2; exit 2; : {dt} {output}";
  CHECK_THROWS_WITH(run_external_level(command, 0.1, out),
                    Contains("exited with status 2") && Contains("cannot converge"));
  // A file left by an earlier run is removed first: a program that writes nothing fails.
  std::ofstream(out) << "t\n0\n";
  command.command = "true {dt} {output}";
  CHECK_THROWS_WITH(run_external_level(command, 0.1, out), Contains("wrote no file"));
  command.command = "printf 'x,y\\n1,2,3\\n' > {output}; : {dt}";
  CHECK_THROWS_AS(run_external_level(command, 0.1, out), core::InputError);
  std::filesystem::remove(out);
}

}  // namespace
}  // namespace flexref::studies
