/// \file cli_fuzz_test.cpp
/// Fuzz target of the command line: random option values over every subcommand of
/// the `flexref` binary, which the test discovers from `flexref --help` and `flexref SUB --help`
/// (so a new command or option is fuzzed without touching this file). Each case runs in its
/// own process group; it must end by itself (a hang fails the test) with an exit code of the
/// table (0 … 5), never a signal or a sanitizer report, say something on a failure, write no
/// output after refusing its input, and write no inf or NaN into a trajectory CSV.
///
/// Output paths are fuzzed too (docs/output.md, "Where outputs go"): links to a file, to a
/// folder and dangling, a FIFO with a reader attached, standard output, a read-only file and a
/// read-only folder; after every case the links are still links, the FIFO still a FIFO without
/// a sidecar, the read-only file and folder as they were, and no temporary or staging folder is
/// left. A second case interrupts every study command with SIGINT, SIGTERM and SIGHUP once its
/// staging folder exists (no clock: the signal follows an event) and requires the end by that
/// signal and nothing left behind.
///
/// A fixed number of cases from a fixed seed, so that the verdict does not depend on the
/// machine's speed or load: FLEXREF_FUZZ_CASES (default 150) and FLEXREF_FUZZ_SEED (default 17)
/// override them; the cases are a prefix of one fixed sequence.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/temp_dir.hpp"

#ifndef FLEXREF_BINARY
#error "FLEXREF_BINARY must name the flexref executable"
#endif

namespace {

namespace fs = std::filesystem;

struct Outcome {
  bool timed_out = false;
  bool signalled = false;
  int signal = 0;
  int code = -1;
  double cpu_seconds = 0.0;  ///< of the process and the children it waited for
  std::string output;        ///< standard output and error
};

/// A case that runs away: more than this CPU time in one process (the kernel then sends
/// SIGXCPU, a signal, which fails the case). A measure of work, not of the clock, so a loaded
/// machine does not reach it sooner: the longest case of the seeded sequence takes at most
/// kLongestCaseCpu of CPU in the Release build (measured 1.5 s, 2026-11-28, shown by the fuzz
/// case's INFO as "the longest took"), and a sanitizer build is at most ~20x slower.
constexpr double kLongestCaseCpu = 2.0;
constexpr rlim_t kCpuLimitSeconds = 60;
static_assert(20.0 * kLongestCaseCpu < static_cast<double>(kCpuLimitSeconds));
/// A case that waits forever without computing (for input that never comes) uses no CPU: this
/// wall-time ceiling ends it. It is far above any case's CPU limit times the slowdown of a
/// loaded machine, so that only such a hang reaches it.
constexpr std::chrono::seconds kWallCeiling(1800);

/// Starts flexref with `args` (from the repository root) in its own process group, its output
/// in `log`, with the signals it handles at their defaults. The sanitizers get exit codes
/// outside the table, so that a report cannot pass for "bad input" (their default exit code
/// is 1).
pid_t start(const std::vector<std::string>& args, const fs::path& log, bool plots) {
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    setpgid(0, 0);
    const rlimit cpu{kCpuLimitSeconds, kCpuLimitSeconds + 1};
    setrlimit(RLIMIT_CPU, &cpu);
    // The signals the program handles, as a shell's foreground command gets them.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) signal(s, SIG_DFL);
    std::FILE* out = std::fopen(log.c_str(), "w");
    if (out == nullptr) _exit(120);
    dup2(fileno(out), STDOUT_FILENO);
    dup2(fileno(out), STDERR_FILENO);
    setenv("ASAN_OPTIONS", "exitcode=86:detect_leaks=1", 1);
    setenv("UBSAN_OPTIONS", "halt_on_error=1:exitcode=87:print_stacktrace=1", 1);
    setenv("FLEXREF_PROGRESS", "off", 1);
    if (!plots) setenv("FLEXREF_PLOT_SCRIPT_DIR", "/nonexistent-flexref-fuzz", 1);
    std::vector<char*> argv;
    std::string binary = FLEXREF_BINARY;
    argv.push_back(binary.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(121);
  }
  return pid;
}

/// Runs flexref with `args` (from the repository root) under the CPU limit above, killing its
/// process group only past the wall-time ceiling (a hang that does not compute).
Outcome run(const std::vector<std::string>& args, const fs::path& log, bool plots) {
  const pid_t pid = start(args, log, plots);
  Outcome outcome;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  rusage usage{};
  while (true) {
    const pid_t done = wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) break;
    if (std::chrono::steady_clock::now() - start > kWallCeiling) {
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      outcome.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(-pid, SIGKILL);  // plot scripts or other children left behind
  if (!outcome.timed_out) {
    outcome.signalled = WIFSIGNALED(status);
    outcome.signal = outcome.signalled ? WTERMSIG(status) : 0;
    outcome.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    outcome.cpu_seconds =
        static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
        1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  }
  std::ifstream in(log);
  std::ostringstream text;
  text << in.rdbuf();
  outcome.output = text.str();
  return outcome;
}

struct OptionSpec {
  std::string name;  ///< "--dt", or a positional's name
  bool takes_value = false;
  bool required = false;
  std::vector<std::string> choices;  ///< from "{a,b,c}" in the type
};

struct CommandSpec {
  std::string name;
  std::vector<OptionSpec> positionals;
  std::vector<OptionSpec> options;
};

std::vector<std::string> split(const std::string& s, char separator) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, separator)) out.push_back(item);
  return out;
}

/// One "  NAME TYPE ...   description" line of CLI11's help, or nothing for a continuation.
bool parse_option_line(const std::string& line, OptionSpec& spec) {
  if (line.size() < 3 || line[0] != ' ' || line[1] != ' ' || line[2] == ' ') return false;
  std::istringstream words(line);
  std::string names, type;
  words >> names >> type;
  for (const std::string& n : split(names, ',')) {
    const std::string bare = n.substr(0, n.find('{'));
    if (bare.rfind("--", 0) == 0 || (spec.name.empty() && bare[0] != '-')) spec.name = bare;
  }
  if (spec.name.empty()) spec.name = names.substr(0, names.find(','));
  const bool type_word =
      !type.empty() && (std::isupper(static_cast<unsigned char>(type[0])) || type[0] == '[');
  spec.takes_value = type_word && type != "Excludes:" && type != "Needs:";
  spec.required = line.find("REQUIRED") != std::string::npos;
  const auto open = type.find('{');
  const auto close = type.find('}');
  if (type_word && open != std::string::npos && close != std::string::npos) {
    spec.choices = split(type.substr(open + 1, close - open - 1), ',');
  }
  return true;
}

CommandSpec parse_help(const std::string& name, const std::string& help) {
  CommandSpec spec;
  spec.name = name;
  std::istringstream in(help);
  std::string line, section;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != ' ') {
      section = line;
      continue;
    }
    OptionSpec option;
    if (!parse_option_line(line, option)) continue;
    if (section.rfind("Positionals", 0) == 0) {
      option.takes_value = true;
      spec.positionals.push_back(option);
    } else if (section.rfind("Options", 0) == 0 && option.name != "--help" &&
               option.name != "--version" && option.name != "-h") {
      spec.options.push_back(option);
    }
  }
  return spec;
}

std::vector<std::string> subcommands(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream in(help);
  std::string line;
  bool in_list = false;
  while (std::getline(in, line)) {
    if (line.rfind("Subcommands", 0) == 0) {
      in_list = true;
      continue;
    }
    if (in_list && line.size() > 2 && line[0] == ' ' && line[2] != ' ') {
      std::istringstream words(line);
      std::string word;
      words >> word;
      names.push_back(word);
    } else if (in_list && !line.empty() && line[0] != ' ') {
      in_list = false;
    }
  }
  return names;
}

/// Values at the edges of what the options accept (overflow, zero, NaN spellings) and their
/// neighbours.
const std::vector<std::string> kNumbers = {
    "0",     "-1",        "1",     "2",     "3",     "16",     "0.5",   "1e-3",  "1e-2",
    "0.003", "1e-9",      "1e-12", "1e-19", "1e-20", "1e-300", "1e300", "1e308", "1e400",
    "-5",    "nan",       "inf",   "-inf",  "abc",   "",       "1,2",   "0,5",   "1e-4,0.1",
    "2.5",   "100000000", "0x10",  "1e6",   "200",   "-0",     " 1",    "1e-6"};
const std::vector<std::string> kNames = {
    "c1",      "c2",   "nmb", "cvode", "ida",   "odeint",   "exact",  "auto",  "lte",
    "coupled", "spin", "rk4", "",      "c1,c2", "rotation", "points", "modes", "foo,bar"};

struct Fixture {
  fs::path dir;
  std::vector<std::string> scenes;
  std::vector<std::string> csvs;
  std::vector<std::string> studies;
};

/// A FIFO with a reader attached for the whole fuzz: a thread holds it open for reading and
/// writing (so a writer's open never waits, and the reader never sees an end) and drains it.
class FifoReader {
 public:
  explicit FifoReader(const fs::path& path) : path_(path) {
    REQUIRE(mkfifo(path.c_str(), 0600) == 0);
    fd_ = open(path.c_str(), O_RDWR | O_NONBLOCK);
    REQUIRE(fd_ >= 0);
    thread_ = std::thread([this] {
      char buffer[1 << 16];
      pollfd p{fd_, POLLIN, 0};
      while (!stop_) {
        if (poll(&p, 1, 50) > 0) bytes_ += std::max<ssize_t>(0, read(fd_, buffer, sizeof buffer));
      }
    });
  }
  ~FifoReader() {
    stop_ = true;
    thread_.join();
    close(fd_);
  }
  FifoReader(const FifoReader&) = delete;
  FifoReader& operator=(const FifoReader&) = delete;
  long bytes() const { return bytes_; }

 private:
  fs::path path_;
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<long> bytes_{0};
  std::thread thread_;
};

/// The output-path fixtures (made by make_output_fixtures) and what must stay true of them.
struct OutputFixtures {
  fs::path file_link;      ///< -> a regular file
  fs::path folder_link;    ///< -> a folder
  fs::path fifo;           ///< with a FifoReader attached
  fs::path readonly_file;  ///< mode 0444, "precious"
  fs::path readonly_dir;   ///< mode 0555, holding "kept.csv"
};

OutputFixtures make_output_fixtures(const fs::path& dir) {
  OutputFixtures o;
  std::ofstream(dir / "link_target.csv") << "t\n0\n";
  o.file_link = dir / "file_link.csv";
  fs::create_symlink("link_target.csv", o.file_link);
  fs::create_directories(dir / "linked_folder");
  o.folder_link = dir / "folder_link";
  fs::create_symlink("linked_folder", o.folder_link);
  o.fifo = dir / "fifo";
  o.readonly_file = dir / "readonly.csv";
  std::ofstream(o.readonly_file) << "precious\n";
  chmod(o.readonly_file.c_str(), 0444);
  o.readonly_dir = dir / "readonly_dir";
  fs::create_directories(o.readonly_dir);
  std::ofstream(o.readonly_dir / "kept.csv") << "kept\n";
  chmod(o.readonly_dir.c_str(), 0555);
  return o;
}

bool is_leftover(const std::string& name) {
  return name.find(".staging-") != std::string::npos || name.find(".tmp-") != std::string::npos ||
         name.find(".previous-") != std::string::npos;
}

/// What a case broke among the output fixtures, or "" (links replaced, the FIFO replaced or
/// given a sidecar, a read-only file or folder changed, a temporary or staging folder left).
std::string broken_fixture(const Fixture& f, const OutputFixtures& o) {
  struct stat st {};
  for (const fs::path& link : {o.file_link, o.folder_link}) {
    if (lstat(link.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return link.string() + " is no link";
  }
  if (lstat(o.fifo.c_str(), &st) != 0 || !S_ISFIFO(st.st_mode)) return "the FIFO was replaced";
  if (fs::exists(o.fifo.string() + ".meta.toml")) return "a sidecar beside the FIFO";
  std::ifstream in(o.readonly_file);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  if (text != "precious\n") return "the read-only file was written";
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(o.readonly_dir)) names.insert(e.path().filename());
  if (names != std::set<std::string>{"kept.csv"}) return "the read-only folder was written";
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(f.dir, ec);
       it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (is_leftover(it->path().filename().string())) return "left behind: " + it->path().string();
  }
  return "";
}

std::string pick(std::mt19937& rng, const std::vector<std::string>& from) {
  return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng)];
}

bool chance(std::mt19937& rng, double p) { return std::bernoulli_distribution(p)(rng); }

std::string output_path(std::mt19937& rng, const Fixture& f, const OutputFixtures& o,
                        int case_number, bool folder) {
  const std::string fresh = (f.dir / ("out" + std::to_string(case_number))).string();
  const int r = std::uniform_int_distribution<int>(0, 99)(rng);
  if (r < 45) return fresh + (folder ? "" : ".csv");
  if (r < 50) return (f.dir / "file.txt" / "sub").string();  // under a file
  if (r < 55) return f.dir.string();                         // an existing non-study folder
  // A missing folder (a study creates it, a file is refused): inside the fixture, since a study
  // run as root would create it anywhere.
  if (r < 60) return (f.dir / "missing" / "out").string();
  if (r < 63) return "";
  if (r < 68) return o.file_link.string();
  if (r < 73) {
    // A dangling link, made for this case: written, it creates its target.
    const fs::path link = f.dir / ("dangling" + std::to_string(case_number));
    fs::create_symlink("made" + std::to_string(case_number), link);
    return link.string();
  }
  if (r < 78) return o.folder_link.string();
  if (r < 83) return o.fifo.string();
  if (r < 88) return o.readonly_file.string();
  if (r < 93) return (o.readonly_dir / (folder ? "study" : "x.csv")).string();
  if (r < 96) return o.readonly_dir.string();
  return folder ? fresh : "-";  // standard output (a folder named "-" would land in the cwd)
}

std::string value_for(std::mt19937& rng, const OptionSpec& option, const Fixture& f,
                      const OutputFixtures& o, int case_number) {
  const std::string& n = option.name;
  if (n == "-o" || n == "--output") return output_path(rng, f, o, case_number, false);
  if (n == "--out") return output_path(rng, f, o, case_number, true);
  if (n == "scene") return pick(rng, f.scenes);
  if (n == "run" || n == "reference") return pick(rng, f.csvs);
  if (n == "study") return pick(rng, f.studies);
  if (!option.choices.empty() && chance(rng, 0.7)) {
    std::string v = pick(rng, option.choices);
    if (chance(rng, 0.2)) v += "," + pick(rng, option.choices);
    return v;
  }
  return chance(rng, 0.8) ? pick(rng, kNumbers) : pick(rng, kNames);
}

/// Trajectory CSVs may not hold inf or NaN (dissipated_work is NaN by design when an
/// integrator does not track it: docs/output.md).
std::string non_finite_cell(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  if (!std::getline(in, line)) return "";
  const std::vector<std::string> header = split(line, ',');
  if (header.empty() || header[0] != "t") return "";  // not a trajectory
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line, ',');
    for (std::size_t i = 0; i < cells.size() && i < header.size(); ++i) {
      if (header[i] == "dissipated_work" || header[i] == "energy_balance") continue;
      const std::string& c = cells[i];
      if (c.find("inf") != std::string::npos || c.find("nan") != std::string::npos) {
        return header[i] + " = " + c;
      }
    }
  }
  return "";
}

double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v != nullptr ? std::atof(v) : fallback;
}

TEST_CASE("fuzzed command lines end with a clear answer and an exit code of the table",
          "[app][fuzz]") {
  const flexref::testing::TempDir tmp("cli-fuzz");
  Fixture f;
  f.dir = tmp.path();
  std::ofstream(f.dir / "file.txt") << "not a folder";
  std::ofstream(f.dir / "empty.toml");
  std::ofstream(f.dir / "garbage.toml") << "[scene\nname = = 3\n\x01\x02";
  const OutputFixtures outputs = make_output_fixtures(f.dir);
  const FifoReader fifo_reader(outputs.fifo);
  // Short scenes (a fraction of a second of simulated time) keep each case fast.
  for (const char* scene : {"free_spin", "book_toss", "bouncing_ball", "flexible_spinner"}) {
    std::ifstream in(std::string("scenes/") + scene + ".toml");
    REQUIRE(in);
    std::ostringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const auto end = s.find("\nend_time");
    const auto eol = s.find('\n', end + 1);
    REQUIRE(end != std::string::npos);
    s.replace(end + 1, eol - end - 1, "end_time = 0.2");
    const auto step = s.find("\noutput_step");
    const auto step_eol = s.find('\n', step + 1);
    s.replace(step + 1, step_eol - step - 1, "output_step = 0.02");
    const fs::path path = f.dir / (std::string(scene) + ".toml");
    std::ofstream(path) << s;
    f.scenes.push_back(path.string());
  }
  f.scenes.insert(f.scenes.end(),
                  {(f.dir / "empty.toml").string(), (f.dir / "garbage.toml").string(),
                   "/nonexistent.toml", f.dir.string(), ""});
  // A run CSV to compare (and a corrupt copy).
  const Outcome made = run({"run", f.scenes[0], "--dt", "1e-3", "-o", (f.dir / "run.csv").string()},
                           f.dir / "setup.log", false);
  REQUIRE(made.code == 0);
  f.csvs = {(f.dir / "run.csv").string(), (f.dir / "file.txt").string(), "/nonexistent.csv",
            f.scenes[0]};
  std::ofstream(f.dir / "fig.toml")
      << "[figure]\nscene = \"" << f.scenes[0] << "\"\nsteps = [0.01, 0.05]\n";
  std::ofstream(f.dir / "fig_bad.toml")
      << "[figure]\nscene = \"" << f.scenes[0] << "\"\nsteps = [1e-300, -1]\n";
  f.studies = {(f.dir / "fig.toml").string(), (f.dir / "fig_bad.toml").string(),
               (f.dir / "garbage.toml").string(), "/nonexistent.toml"};

  const Outcome top = run({"--help"}, f.dir / "help.log", false);
  REQUIRE(top.code == 0);
  std::vector<CommandSpec> commands;
  for (const std::string& name : subcommands(top.output)) {
    const Outcome help = run({name, "--help"}, f.dir / "help.log", false);
    REQUIRE(help.code == 0);
    commands.push_back(parse_help(name, help.output));
  }
  REQUIRE(commands.size() >= 9);  // check, run, reference, compare, converge, …

  const auto seed = static_cast<unsigned>(env_or("FLEXREF_FUZZ_SEED", 17));
  // 150 cases by default, whatever the machine: the checks below need the sequence to reach
  // past parsing (seed 17: the first success is past case 48; 150 cases hold successes,
  // refusals and parse errors), and every build runs the same prefix of the seeded sequence.
  const int case_count = static_cast<int>(env_or("FLEXREF_FUZZ_CASES", 150));
  std::mt19937 rng(seed);
  std::map<int, int> codes;
  int cases = 0;
  double max_cpu = 0.0;
  while (cases < case_count) {
    ++cases;
    const CommandSpec& command =
        commands[std::uniform_int_distribution<std::size_t>(0, commands.size() - 1)(rng)];
    std::vector<std::string> args{command.name};
    std::string out_path;
    for (const OptionSpec& p : command.positionals) {
      if (p.required || chance(rng, 0.5)) args.push_back(value_for(rng, p, f, outputs, cases));
    }
    const int n_options = std::uniform_int_distribution<int>(0, 4)(rng);
    bool limited = false;
    for (int k = 0; k < n_options && !command.options.empty(); ++k) {
      const OptionSpec& o = command.options[std::uniform_int_distribution<std::size_t>(
          0, command.options.size() - 1)(rng)];
      args.push_back(o.name);
      limited = limited || o.name == "--max-steps";
      if (!o.takes_value) continue;
      args.push_back(value_for(rng, o, f, outputs, cases));
      if (o.name == "-o" || o.name == "--output" || o.name == "--out") out_path = args.back();
    }
    // Most cases keep their runs short through the command's own limit (when it has one).
    for (const OptionSpec& o : command.options) {
      if (o.name == "--max-steps" && !limited && chance(rng, 0.8)) {
        args.insert(args.end(), {"--max-steps", "20000"});
      }
      if (o.name == "--out" && out_path.empty() && chance(rng, 0.9)) {
        out_path = output_path(rng, f, outputs, cases, true);
        args.insert(args.end(), {"--out", out_path});
      }
    }
    std::string line = "flexref";
    for (const std::string& a : args) line += " '" + a + "'";
    INFO("case " << cases << " (seed " << seed << "): " << line);
    const Outcome o = run(args, f.dir / "case.log", chance(rng, 0.2));
    INFO("output:\n" << o.output.substr(0, 3000));
    INFO("signal " << o.signal << (o.signal == SIGXCPU ? " (over the CPU limit: a runaway)" : "")
                   << ", CPU " << o.cpu_seconds << " s");
    max_cpu = std::max(max_cpu, o.cpu_seconds);
    REQUIRE_FALSE(o.timed_out);  // waited past the wall-time ceiling: a hang
    REQUIRE_FALSE(o.signalled);
    REQUIRE(o.code >= 0);
    REQUIRE(o.code <= 5);
    REQUIRE(o.output.find("runtime error") == std::string::npos);
    REQUIRE(o.output.find("Sanitizer") == std::string::npos);
    ++codes[o.code];
    if (o.code != 0) REQUIRE_FALSE(o.output.empty());
    if ((o.code == 1 || o.code == 2) && !out_path.empty() &&
        out_path.find(("out" + std::to_string(cases))) != std::string::npos) {
      // Refused input writes nothing.
      REQUIRE_FALSE(fs::exists(out_path));
    }
    const std::string broken = broken_fixture(f, outputs);
    INFO("output fixture: " << broken);
    REQUIRE(broken.empty());
    if (o.code == 0 && !out_path.empty() && fs::is_regular_file(out_path)) {
      REQUIRE(non_finite_cell(out_path).empty());
    }
    if (o.code == 0 && !out_path.empty() && fs::is_directory(out_path)) {
      for (const auto& entry : fs::directory_iterator(out_path)) {
        if (entry.path().extension() == ".csv" && entry.path().filename() != "convergence.csv" &&
            entry.path().filename() != "work_precision.csv") {
          INFO(entry.path());
          REQUIRE(non_finite_cell(entry.path()).empty());
        }
      }
    }
  }
  std::ostringstream summary;
  for (const auto& [code, count] : codes) summary << " exit " << code << ": " << count << ";";
  INFO(cases << " fuzzed command lines (seed " << seed << "):" << summary.str()
             << " the longest took " << max_cpu << " s of CPU");
  // (max_cpu is reported, not checked: CPU time scales with the build, ~20x under the
  // sanitizers, and the CPU limit above already fails a runaway case.)
  // The sequence must reach past parsing: some cases succeed and some are refused as input.
  CHECK(codes[0] > 0);
  CHECK(codes[2] > 0);
  CHECK(codes[1] > 0);
}

/// The names in `dir` that start with `prefix` (a study's staging or previous folder).
std::vector<std::string> entries_with_prefix(const fs::path& dir, const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0) out.push_back(name);
  }
  return out;
}

/// A long run of each study command: a full bundled scene (or a paper study), so that the
/// signal always finds it computing.
std::vector<std::string> long_study(const CommandSpec& command, const fs::path& out) {
  std::vector<std::string> args{command.name};
  for (const OptionSpec& p : command.positionals) {
    if (p.name == "scene") {
      // modes keeps up to 64 modes by default: the 64-mode scene.
      const bool wear = command.name == "wear" || command.name == "wear-jump";
      args.push_back(command.name == "modes"     ? "scenes/flexible_spinner_64.toml"
                     : command.name == "lte-map" ? "scenes/flexible_spinner.toml"
                     : wear                      ? "scenes/tube_support_wear.toml"
                                                 : "scenes/book_toss.toml");
    } else if (p.name == "study") {
      args.push_back("studies/paper/fig1_free_spin.toml");
    }
  }
  args.insert(args.end(), {"--out", out.string()});
  return args;
}

/// The text of a file ("" when it cannot be read).
std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST_CASE("every output option is tried with every kind of path", "[app][fuzz]") {
  const flexref::testing::TempDir tmp("cli-outputs");
  Fixture f;
  f.dir = tmp.path();
  const OutputFixtures outputs = make_output_fixtures(f.dir);
  const FifoReader fifo_reader(outputs.fifo);
  // Short scenes (0.2 s) and a figure study keep each accepted case short; lte-map and modes
  // need a flexible body, wear and wear-jump a contact with a wear law.
  const auto shortened = [&](const std::string& name) {
    std::ifstream in("scenes/" + name + ".toml");
    REQUIRE(in);
    std::string scene((std::istreambuf_iterator<char>(in)), {});
    const auto end = scene.find("\nend_time");
    REQUIRE(end != std::string::npos);
    scene.replace(end + 1, scene.find('\n', end + 1) - end - 1, "end_time = 0.2");
    const auto step = scene.find("\noutput_step");
    REQUIRE(step != std::string::npos);
    scene.replace(step + 1, scene.find('\n', step + 1) - step - 1, "output_step = 0.02");
    const fs::path path = f.dir / (name + ".toml");
    std::ofstream(path) << scene;
    return path;
  };
  const fs::path scene_path = shortened("free_spin");
  const fs::path flexible_path = shortened("flexible_spinner");
  const fs::path wear_path = shortened("wear_block");
  std::ofstream(f.dir / "fig.toml")
      << "[figure]\nscene = \"" << scene_path.string() << "\"\nsteps = [0.01, 0.05]\n";
  fs::create_directories(f.dir / "not_a_study");
  std::ofstream(f.dir / "not_a_study" / "notes.md") << "mine\n";

  const Outcome top = run({"--help"}, f.dir / "help.log", false);
  REQUIRE(top.code == 0);
  int file_commands = 0, folder_commands = 0;
  for (const std::string& name : subcommands(top.output)) {
    const Outcome help = run({name, "--help"}, f.dir / "help.log", false);
    const CommandSpec command = parse_help(name, help.output);
    std::string option;
    for (const OptionSpec& o : command.options) {
      if (o.name == "--output" || o.name == "--out") option = o.name;
    }
    // Commands whose positionals this test can fill (a scene or a study file).
    std::vector<std::string> base{name};
    bool fillable = !option.empty();
    for (const OptionSpec& p : command.positionals) {
      if (p.name == "scene") {
        const bool flexible = name == "lte-map" || name == "modes";
        const bool wear = name == "wear" || name == "wear-jump";
        base.push_back((flexible ? flexible_path : wear ? wear_path : scene_path).string());
      } else if (p.name == "study") {
        base.push_back((f.dir / "fig.toml").string());
      } else if (p.required) {
        fillable = false;
      }
    }
    if (!fillable) continue;
    const bool folder = option == "--out";
    (folder ? folder_commands : file_commands) += 1;
    struct Kind {
      std::string what;
      fs::path path;
      bool accepted;
    };
    std::vector<Kind> kinds = {
        {"a link to a folder", outputs.folder_link, folder},
        {"a link to a file", outputs.file_link, !folder},
        {"a FIFO", outputs.fifo, !folder},
        {"a read-only file", outputs.readonly_file, false},
        {"a path in a read-only folder", outputs.readonly_dir / "new", false},
        {"a read-only folder", outputs.readonly_dir, false},
        {"a folder that is not a study's", f.dir / "not_a_study", false},
    };
    // The accepted folder cases run a whole study: one command is enough for them (every study
    // writes through the same StudyOutput); files are cheap.
    if (!folder || name == "converge") {
      const fs::path dangling = f.dir / ("dangling_" + name);
      fs::create_symlink("made_" + name, dangling);
      kinds.push_back({"a dangling link", dangling, true});
      if (!folder) kinds.push_back({"standard output", "-", true});
    }
    for (const Kind& kind : kinds) {
      if (kind.accepted && folder && name != "converge") continue;
      std::vector<std::string> args = base;
      args.insert(args.end(), {option, kind.path.string()});
      std::string line = "flexref";
      for (const std::string& a : args) line += " '" + a + "'";
      INFO(line << " (" << kind.what << ")");
      const long fifo_bytes = fifo_reader.bytes();
      const Outcome o = run(args, f.dir / "case.log", false);
      INFO("output:\n" << o.output.substr(0, 3000));
      REQUIRE_FALSE(o.timed_out);
      REQUIRE_FALSE(o.signalled);
      CHECK(o.code == (kind.accepted ? 0 : 5));
      const std::string broken = broken_fixture(f, outputs);
      INFO("output fixture: " << broken);
      CHECK(broken.empty());
      if (!kind.accepted) continue;
      if (kind.path == "-") {
        CHECK(o.output.rfind("t,", 0) == 0);  // the CSV first, on standard output
      } else if (kind.path == outputs.fifo) {
        CHECK(fifo_reader.bytes() > fifo_bytes);
      } else if (folder) {
        CHECK(fs::is_symlink(kind.path));
        CHECK(fs::is_regular_file(kind.path / "study.toml"));
      } else {
        CHECK(fs::is_symlink(kind.path));
        CHECK(text_of(kind.path).rfind("t,", 0) == 0);
        // The sidecar beside the link's target (the fixtures' links are relative).
        std::error_code ec;
        const fs::path target = fs::read_symlink(kind.path, ec);
        CHECK(fs::is_regular_file(f.dir / (target.string() + ".meta.toml")));
      }
    }
  }
  CHECK(file_commands >= 2);    // run, reference
  CHECK(folder_commands >= 6);  // converge, work-precision, stability, figure, lte-map, modes
}

TEST_CASE("interrupted studies leave nothing behind and end by the signal", "[app][fuzz]") {
  const flexref::testing::TempDir tmp("cli-signals");
  const fs::path& dir = tmp.path();
  const Outcome top = run({"--help"}, dir / "help.log", false);
  REQUIRE(top.code == 0);
  std::vector<CommandSpec> studies;
  for (const std::string& name : subcommands(top.output)) {
    const Outcome help = run({name, "--help"}, dir / "help.log", false);
    REQUIRE(help.code == 0);
    CommandSpec spec = parse_help(name, help.output);
    for (const OptionSpec& o : spec.options) {
      if (o.name == "--out") studies.push_back(spec);
    }
  }
  REQUIRE(studies.size() >= 8);  // converge, work-precision, stability, figure, lte-map, modes,
                                 // wear, wear-jump
  int interrupted = 0;
  std::string not_interrupted;
  for (const CommandSpec& command : studies) {
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
      // Half the cases replace a previous study's folder, which must survive as it was.
      const std::string name = command.name + "_" + std::to_string(signal_number);
      const fs::path out = dir / name;
      const bool previous = signal_number != SIGTERM;
      if (previous) {
        fs::create_directories(out);
        std::ofstream(out / "study.toml") << "[files]\n";
        std::ofstream(out / "table.csv") << "old\n";
      }
      const std::vector<std::string> args = long_study(command, out);
      std::string line = "flexref";
      for (const std::string& a : args) line += " '" + a + "'";
      INFO(line << ", signal " << signal_number);
      const pid_t pid = start(args, dir / (name + ".log"), true);
      // Wait for the event (the staging folder exists: the study is past its checks), not for
      // a time; the study may also end first (a refusal), which the checks below accept.
      int status = 0;
      bool ended = false;
      const auto since = std::chrono::steady_clock::now();
      while (entries_with_prefix(dir, "." + name + ".staging-").empty()) {
        if (waitpid(pid, &status, WNOHANG) == pid) {
          ended = true;
          break;
        }
        // A guard against a study that never gets to its staging folder (a hang), not a timing:
        // the wall-time ceiling of every case.
        if (std::chrono::steady_clock::now() - since > kWallCeiling) {
          kill(-pid, SIGKILL);
          waitpid(pid, &status, 0);
          FAIL("no staging folder and no end within the wall-time ceiling");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      if (!ended) {
        kill(pid, signal_number);
        REQUIRE(waitpid(pid, &status, 0) == pid);
      }
      kill(-pid, SIGKILL);  // anything of its group left behind
      std::ifstream log(dir / (name + ".log"));
      const std::string output((std::istreambuf_iterator<char>(log)), {});
      INFO("output:\n" << output.substr(0, 3000));
      if (WIFSIGNALED(status)) {
        // Ended by the signal itself (shell status 128 + N), after the cleanup.
        CHECK(WTERMSIG(status) == signal_number);
        CHECK(output.find("flexref: interrupted") != std::string::npos);
        ++interrupted;
      } else {
        REQUIRE(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) <= 5);
        not_interrupted += " " + name + " (exit " + std::to_string(WEXITSTATUS(status)) + ")";
      }
      CHECK(entries_with_prefix(dir, "." + name + ".").empty());
      if (previous && WIFSIGNALED(status)) {
        std::set<std::string> names;
        for (const auto& e : fs::directory_iterator(out)) names.insert(e.path().filename());
        CHECK(names == std::set<std::string>{"study.toml", "table.csv"});
      } else if (WIFSIGNALED(status)) {
        CHECK_FALSE(fs::exists(out));
      }
    }
  }
  // Every long study reaches its staging folder and computes long after it: each case is
  // interrupted (a study that ended first would have been refused or finished in an instant).
  INFO("ended before the signal:" << not_interrupted);
  CHECK(interrupted == 3 * static_cast<int>(studies.size()));
}

}  // namespace
