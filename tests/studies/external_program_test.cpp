/// Running another code's integrator (studies/external_program.hpp): the substituted command,
/// its exit status, output tail, CPU time and timeout, and the file it writes read under the
/// trajectory contract.
#include "studies/external_program.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "tests/support/temp_dir.hpp"

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
  // A busy loop in a child of the shell that prints, at its end, the CPU time it used by its
  // own clock: wait4 counts the grandchild's time (the shell waited for it), so the outcome's
  // CPU time is at least that reading, whatever the load (both are CPU time, not wall time).
  // Slack: one scheduler tick, 1e-2 s at the coarsest Linux accounting (HZ = 100).
  const ProgramOutcome busy = run_program(
      "/usr/bin/python3 -c 'import time\nt = time.process_time()\n"
      "while time.process_time() - t < 0.2: pass\nprint(repr(time.process_time()))'; true",
      0.0);
  CHECK(busy.exit_status == 0);
  const double reported = std::stod(busy.output_tail);
  CHECK(reported >= 0.2);
  CHECK(busy.cpu_seconds >= reported - 1e-2);
  // The timeout kills the whole process group (the shell and its sleep); the command never
  // ends by itself, so only the timeout can end it.
  const ProgramOutcome slow = run_program("while :; do sleep 1; done; echo never", 0.2);
  CHECK(slow.timed_out);
  CHECK(slow.signal == 9);
  CHECK(slow.output_tail.empty());
}

TEST_CASE("a program's own progress: the tail shows each line as a terminal leaves it",
          "[studies][external]") {
  // 20000 progress updates on one line ('\r' between them), then two lines: the tail holds
  // what follows each line's last carriage return, never the overwritten updates.
  const ProgramOutcome chatty = run_program(
      "i=0; while [ $i -lt 20000 ]; do printf 'step %d\r' $i; i=$((i+1)); done; "
      "printf 'step 20000 of 20000\nfailed at t = 3\n'; exit 1",
      0.0);
  CHECK(chatty.exit_status == 1);
  CHECK(chatty.output_tail == "step 20000 of 20000\nfailed at t = 3");
  // 20 MB of progress lines: the tail is the last lines, at most 2000 characters.
  const ProgramOutcome verbose = run_program(
      "/usr/bin/python3 -c 'import sys\nfor i in range(200000): "
      "sys.stdout.write(\"%099d\\n\" % i)\nsys.stderr.write(\"the end\\n\")'",
      0.0);
  CHECK(verbose.exit_status == 0);
  CHECK(verbose.output_tail.size() <= 2000);
  CHECK_THAT(verbose.output_tail, Catch::Matchers::EndsWith("199999\nthe end"));
}

TEST_CASE("a level: the program's own CPU report, checked against what it used",
          "[studies][external]") {
  const testing::TempDir tmp("external-report");
  const std::filesystem::path& dir = tmp.path();
  const std::string out = (dir / "run.csv").string();
  ExternalCommand command;
  command.scene = "scene.toml";
  command.command = "printf 't,body.W1\\n0,1\\n# cpu_seconds = 2.5e-3\\n' > {output}; : {dt}";
  const ExternalLevel level = run_external_level(command, 0.1, out);
  CHECK(level.cpu_reported);
  CHECK(level.cpu_seconds == 2.5e-3);
  // printf uses no measurable CPU: a report of 5 s cannot be its integration's.
  command.command = "printf 't,body.W1\\n0,1\\n# cpu_seconds = 5\\n' > {output}; : {dt}";
  CHECK_THROWS_WITH(run_external_level(command, 0.1, out),
                    Contains(":3: key 'cpu_seconds': reports 5 s of CPU"));
  command.command = "printf 't,body.W1\\n0,1\\n# cpu_seconds = soon\\n' > {output}; : {dt}";
  CHECK_THROWS_WITH(run_external_level(command, 0.1, out),
                    Contains("key 'cpu_seconds': expected the integration's CPU time"));
  // Without a report: the whole program's time, not marked as reported.
  command.command = "printf 't,body.W1\\n0,1\\n' > {output}; : {dt}";
  CHECK_FALSE(run_external_level(command, 0.1, out).cpu_reported);
}

TEST_CASE("a level: failures say why, the file is read under the contract", "[studies][external]") {
  const testing::TempDir dir("external-level");
  const std::string out = (dir / "level.csv").string();
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
}

}  // namespace
}  // namespace flexref::studies
