// The sphsplat binary as a user meets it: help, version, bad scenes and flags refused with one
// line and exit code 2, a run with its summary, and the blow-up guard's message and exit code 3.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <regex>
#include <sstream>

#include "io/MessageText.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using test::runSphsplat;
using test::writeTempFile;

// One line of output (no progress noise) that must be exactly the error.
std::string lastLine(const std::string& s) {
  std::string t = s;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  return t.substr(t.rfind('\n') == std::string::npos ? 0 : t.rfind('\n') + 1);
}

TEST(Cli, HelpAndVersion) {
  const auto help = runSphsplat("--help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.output.find("run"), std::string::npos);
  EXPECT_NE(help.output.find("Simulate a scene file"), std::string::npos);
  const auto runHelp = runSphsplat("run --help");
  EXPECT_EQ(runHelp.exitCode, 0);
  for (const char* flag : {"--threads", "--end", "--quiet", "--set", "--verbose", "Exit codes"}) {
    EXPECT_NE(runHelp.output.find(flag), std::string::npos) << flag;
  }
  const auto version = runSphsplat("--version");
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_TRUE(std::regex_search(version.output, std::regex("sphsplat [0-9]+\\.[0-9]+\\.[0-9]+")));
}

TEST(Cli, BadFlagsExitWithTwo) {
  EXPECT_EQ(runSphsplat("").exitCode, 2);
  EXPECT_EQ(runSphsplat("frobnicate").exitCode, 2);
  EXPECT_EQ(runSphsplat("run").exitCode, 2);
  EXPECT_EQ(runSphsplat("run x.json --threads -2").exitCode, 2);
  EXPECT_EQ(runSphsplat("run x.json --end 0").exitCode, 2);
}

// A scene named like an option ("-x.json") is read as options, so the scene is missing: the line
// says how to name it.
TEST(Cli, ASceneNamedLikeAnOptionIsExplained) {
  const auto r = test::runShell(test::sphsplatCommand() + " run -x.json 2>&1");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output,
            "sphsplat: scene is required; -x.json is read as options: name the file ./-x.json "
            "(see sphsplat run --help)\n");
}

// `mpirun -np 3 sphsplat ...` with a build without MPI would start three plain processes that each
// run the whole job and race for one output. The starter's variables are set here by hand: this
// build has no MPI to start (the MPI suite, tests/test_mpi.cpp, covers builds with it).
TEST(Cli, WithoutMpiALaunchAsSeveralProcessesIsRefused) {
#ifdef SPHSPLAT_TEST_MPI_BUILD
  GTEST_SKIP() << "built with MPI: mpirun starts real ranks (tests/test_mpi.cpp)";
#else
  const std::string job = "run " + test::sourcePath("scenes/dam_break.json") + " --end 0.001";
  const auto rank0 = test::runShell("OMPI_COMM_WORLD_SIZE=3 OMPI_COMM_WORLD_RANK=0 " +
                                    test::sphsplatCommand() + " " + job + " 2>&1");
  EXPECT_EQ(rank0.exitCode, 2);
  EXPECT_EQ(rank0.output,
            "sphsplat: started by an MPI launcher as one of 3 processes, but this sphsplat is "
            "built without MPI, so each would run the whole job alone; build the release "
            "preset, which has MPI (scripts/build), or run without mpirun (docs/scaling.md)\n");
  // The other ranks refuse silently: the line is said once.
  const auto rank2 =
      test::runShell("PMI_SIZE=3 PMI_RANK=2 " + test::sphsplatCommand() + " " + job + " 2>&1");
  EXPECT_EQ(rank2.exitCode, 2);
  EXPECT_EQ(rank2.output, "");
  // Slurm's `srun --mpi=pmix -n 4`: PMIx names the rank only, srun the step's size.
  const auto srun = test::runShell("PMIX_RANK=0 SLURM_STEP_NUM_TASKS=4 SLURM_PROCID=0 " +
                                   test::sphsplatCommand() + " " + job + " 2>&1");
  EXPECT_EQ(srun.exitCode, 2);
  EXPECT_NE(srun.output.find("as one of 4 processes"), std::string::npos) << srun.output;
  // A batch script's own shell carries the job's SLURM_* but is one plain process.
  const auto batch = test::runShell("SLURM_STEP_NUM_TASKS=4 SLURM_NTASKS=4 SLURM_PROCID=0 " +
                                    test::sphsplatCommand() + " --version 2>&1");
  EXPECT_EQ(batch.exitCode, 0) << batch.output;
  // One process under a starter is a plain run.
  const auto one =
      test::runShell("OMPI_COMM_WORLD_SIZE=1 " + test::sphsplatCommand() + " --version 2>&1");
  EXPECT_EQ(one.exitCode, 0) << one.output;
#endif
}

struct BadScene {
  const char* what;
  std::string text;
  std::string message;  // expected after "sphsplat: FILE: "
};

TEST(Cli, EveryClassOfBadSceneIsRefusedWithOneLineAndExitTwo) {
  const std::vector<BadScene> cases = {
      {"unknown key",
       R"({"solver": {"spacing": 0.01, "cfll": 1}, "fluids": [{"min": [0,0,0], "max": [0.1,0.1,0.1]}]})",
       "solver.cfll: unknown key (did you mean \"cfl\"?)"},
      {"wrong type",
       R"({"solver": {"spacing": 0.01, "cfl": "fast"}, "fluids": [{"min": [0,0,0], "max": [0.1,0.1,0.1]}]})",
       "solver.cfl: expected a positive number, got the string \"fast\""},
      {"negative spacing",
       R"({"solver": {"spacing": -0.01}, "fluids": [{"min": [0,0,0], "max": [0.1,0.1,0.1]}]})",
       "solver.spacing: expected a positive number of at most 1000 (m), got -0.01"},
      {"fluid outside the domain",
       R"({"solver": {"spacing": 0.01}, "domain": {"min": [0,0,0], "max": [1,1,1]},
        "fluids": [{"min": [0,0,0], "max": [2,0.1,0.1]}]})",
       "fluids[0]: fluid outside the domain"},
      {"zero-size emitter", R"({"solver": {"spacing": 0.01},
        "emitters": [{"position": [0,1,0], "direction": [0,-1,0], "radius": 0, "speed": 1}]})",
       "emitters[0].radius: expected a positive number (m), got 0"},
      {"inverted box",
       R"({"solver": {"spacing": 0.01}, "fluids": [{"min": [0,0,0], "max": [0.1,-0.1,0.1]}]})",
       "fluids[0].max: expected max > min on every axis"},
      {"bad enum",
       R"({"solver": {"spacing": 0.01, "eos": "ideal-gas"}, "fluids": [{"min": [0,0,0], "max": [0.1,0.1,0.1]}]})",
       "solver.eos: expected one of \"tait\", \"linear\", got the string \"ideal-gas\""},
  };
  for (const BadScene& c : cases) {
    const std::string path = writeTempFile(c.text);
    const auto r = runSphsplat("run " + path);
    // --check refuses it the same, without simulating.
    const auto checked = runSphsplat("run " + path + " --check");
    EXPECT_EQ(checked.exitCode, 2) << c.what << "\n" << checked.output;
    EXPECT_EQ(lastLine(checked.output), lastLine(r.output)) << c.what;
    EXPECT_EQ(r.exitCode, 2) << c.what << "\n" << r.output;
    EXPECT_EQ(lastLine(r.output).rfind("sphsplat: " + path + ": " + c.message, 0), 0u)
        << c.what << ": got\n"
        << r.output;
    EXPECT_EQ(r.output.find("done"), std::string::npos) << c.what << ": something ran";
  }
  const auto missing = runSphsplat("run /nonexistent/nope.json");
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_EQ(
      lastLine(missing.output),
      "sphsplat: /nonexistent/nope.json: cannot open the scene file (No such file or directory)");
  const auto syntax = runSphsplat("run " + writeTempFile("{\"solver\": {\"spacing\": 0.01,,}}"));
  EXPECT_EQ(syntax.exitCode, 2);
  EXPECT_NE(syntax.output.find(":1:"), std::string::npos) << syntax.output;
  const auto badSet =
      runSphsplat("run " + test::sourcePath("scenes/dam_break.json") + " --set solver.spacing=-1");
  EXPECT_EQ(badSet.exitCode, 2);
  EXPECT_NE(
      badSet.output.find("solver.spacing: expected a positive number of at most 1000 (m), got -1"),
      std::string::npos);
}

TEST(Cli, CheckValidatesTheSceneWithoutRunningOrWriting) {
  const std::string dir = test::makeTempDirectory("sphsplat-check");
  const auto r = runSphsplat("run " + test::sourcePath("scenes/dam_break.json") + " --check -o " +
                             dir + "/never.h5");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("a valid scene (dam_break); memory: about "), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("6400 fluid particles"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("done"), std::string::npos) << "it simulated:\n" << r.output;
  EXPECT_NE(access((dir + "/never.h5").c_str(), F_OK), 0) << "it wrote a cache";
  // A scene past what a run takes is refused as the run would refuse it.
  const auto big = runSphsplat("run " + test::sourcePath("scenes/dam_break.json") +
                               " --set solver.spacing=0.0002 --check");
  EXPECT_EQ(big.exitCode, 2) << big.output;
  EXPECT_NE(big.output.find("(raise the spacing)"), std::string::npos) << big.output;
}

TEST(Cli, RunPrintsProgressLinesAndASummary) {
  const auto r = runSphsplat("run " + test::sourcePath("scenes/dam_break.json") +
                             " --set solver.spacing=0.02 --end 0.05 --threads 2");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(
      std::regex_search(r.output, std::regex("dam_break: [0-9]+ fluid particles, [0-9]+ boundary")))
      << r.output;
  EXPECT_NE(r.output.find("dam_break 100%"), std::string::npos)
      << r.output;  // plain progress lines
  EXPECT_NE(r.output.find("done: simulated 0.05 s"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("particle-steps/s"), std::string::npos);
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << "no bar redraws when not a terminal";
  const auto quiet = runSphsplat("run " + test::sourcePath("scenes/dam_break.json") +
                                 " --set solver.spacing=0.02 --end 0.01 --quiet");
  EXPECT_EQ(quiet.exitCode, 0);
  EXPECT_EQ(quiet.output, "");
}

TEST(Cli, BlowUpStopsWithStepTimeParticleAndExitThree) {
  // A block thrown at 80 m/s in a small open domain: the guard stops it when it leaves.
  const std::string path =
      writeTempFile(R"({"solver": {"spacing": 0.01, "gravity": [0,0,0], "speed_of_sound": 20},
    "domain": {"min": [-0.1,-0.1,-0.1], "max": [0.3,0.3,0.3]},
    "fluids": [{"min": [0,0,0], "max": [0.05,0.05,0.05], "velocity": [80,0,0]}]})");
  const auto r = runSphsplat("run " + path);
  EXPECT_EQ(r.exitCode, 3) << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output,
      std::regex(
          "numerical blow-up at step [0-9]+, t = [0-9.e-]+ s: particle [0-9]+ left the domain")))
      << r.output;
  EXPECT_NE(r.output.find("reproduce: sphsplat run " + path + " --end"), std::string::npos)
      << r.output;
  // The reproduce line runs as printed and ends in the same blow-up: its --end is rounded up,
  // never down past the failing step.
  const std::size_t at = r.output.find("reproduce: sphsplat ");
  ASSERT_NE(at, std::string::npos);
  const std::size_t from = at + std::string("reproduce: sphsplat ").size();
  const std::string arguments = r.output.substr(from, r.output.find('\n', from) - from);
  const auto again = runSphsplat(arguments);
  EXPECT_EQ(again.exitCode, 3) << arguments << "\n" << again.output;
  const std::string blowUp = r.output.substr(r.output.find("numerical blow-up"));
  EXPECT_EQ(again.output.substr(again.output.find("numerical blow-up")).substr(0, 80),
            blowUp.substr(0, 80));
}

// One line on stderr, printable ASCII, short: what every refusal must be (docs/reliability.md,
// "Bad input is one line and exit 2").
::testing::AssertionResult oneShortLine(const test::CommandResult& r) {
  const std::string& m = r.output;
  if (r.exitCode != 2) return ::testing::AssertionFailure() << "exit " << r.exitCode << ": " << m;
  if (m.empty() || m.back() != '\n' || m.find('\n') != m.size() - 1)
    return ::testing::AssertionFailure() << "not one line: " << m.substr(0, 500);
  if (m.size() > 320) return ::testing::AssertionFailure() << m.size() << " characters";
  for (const char c : m.substr(0, m.size() - 1)) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b >= 0x7f)
      return ::testing::AssertionFailure() << "byte " << int(b) << ": " << m;
  }
  return ::testing::AssertionSuccess();
}

struct Hostile {
  std::string what, path, message;  // message: the line after "sphsplat: PATH"
};

TEST(Cli, HostileScenesAreRefusedWithOneShortLine) {
  const std::string dir = writeTempFile("", "") + ".d";
  ASSERT_EQ(std::system(("mkdir '" + dir + "'").c_str()), 0);
  const std::string fifo = dir + "/fifo.json";
  ASSERT_EQ(std::system(("mkfifo '" + fifo + "'").c_str()), 0);
  const std::string big = dir + "/big.json";
  ASSERT_EQ(std::system(("truncate -s 65M '" + big + "'").c_str()), 0);
  const std::vector<Hostile> cases = {
      // Overflowed nlohmann's recursion: exit 139.
      {"deep nesting", writeTempFile(std::string(70000, '[') + std::string(70000, ']')),
       ":1:65: nested deeper than 64 levels of [ and {; expected at most 64"},
      // A 10 MB number: a 10 MB "internal error" line, exit 1.
      {"ten million digits",
       writeTempFile("{\"solver\": {\"spacing\": 1" + std::string(10000000, '0') + "}}"),
       ":1:24: a number of 1e7 characters; expected at most 64 (a double keeps 17 significant "
       "digits)"},
      {"duplicate section",
       writeTempFile("{\"solver\": {\"spacing\": 0.01},\n \"solver\": {\"cfl\": 0.3}}"),
       ":2:2: duplicate key solver (first given at 1:2); expected each key once (JSON keeps only "
       "one of the two)"},
      // "unexpected end of input" before.
      {"a directory", dir, ": is a directory; expected a scene file"},
      // Read forever before.
      {"/dev/zero", "/dev/zero",
       ": is a character device, not a regular file; expected a scene file"},
      {"a FIFO", fifo, ": is a FIFO (named pipe), not a regular file; expected a scene file"},
      {"65 MiB", big, ": 65 MiB is too large for a scene file (at most 64 MiB)"},
      // Printed a raw 0xFF byte before.
      {"UTF-16", writeTempFile(std::string("\xFF\xFE{\0\"\0s\0\"\0:\0{\0}\0}\0", 18)),
       ": not UTF-8 text: it looks like UTF-16 little-endian (byte-order mark FF FE); save it as "
       "UTF-8"},
  };
  for (const Hostile& c : cases) {
    const auto r =
        test::runShell("timeout 60 " + test::sphsplatCommand() + " run '" + c.path + "'");
    EXPECT_TRUE(oneShortLine(r)) << c.what;
    EXPECT_EQ(r.output, "sphsplat: " + c.path + c.message + "\n") << c.what;
  }
}

// A newline or ESC in a path or a scene's name neither splits an error line nor reaches the
// terminal: both are written as \xHH (valid UTF-8 stays as it is).
TEST(Cli, NamesWithControlBytesStayOneLineAndPrintable) {
  const std::string dir = test::makeTempDirectory("sphsplat-names");
  const std::string odd = dir + "/we\x1b[1mird\ndir";
  ASSERT_EQ(::mkdir(odd.c_str(), 0755), 0);
  auto r = test::runShell("timeout 60 " + test::sphsplatCommand() + " run '" + odd + "/nope.json'");
  EXPECT_TRUE(oneShortLine(r)) << r.output;
  EXPECT_EQ(r.output, "sphsplat: " + dir + "/we\\x1B[1mird\\x0Adir/nope.json: cannot open the scene "
                      "file (No such file or directory)\n");
  const std::string named = writeTempFile("{\"name\": \"a\\u001b[31mb\\nc\", \"solver\": "
                                          "{\"spacing\": 0.05}, \"fluids\": [{\"min\": [0,0,0], "
                                          "\"max\": [0.1,0.1,0.1]}]}");
  r = test::runShell("timeout 60 " + test::sphsplatCommand() + " run '" + named + "' --check");
  EXPECT_TRUE(oneShortLine(r)) << r.output;
  EXPECT_NE(r.output.find("name: expected a name without control characters or bytes that are "
                          "not UTF-8, got \"a\\x1B[31mb\\x0Ac\""),
            std::string::npos)
      << r.output;
  EXPECT_EQ(io::oneLine("caf\xc3\xa9 \xe6\xb0\xb4"), "caf\xc3\xa9 \xe6\xb0\xb4");  // kept
  EXPECT_EQ(io::oneLine("a\xc2\x9b[1m\xff\xc3"), "a\\xC2\\x9B[1m\\xFF\\xC3");  // C1, not UTF-8
}

TEST(Cli, ThreadsAreCappedInEverySubcommand) {
  const std::string scene = test::sourcePath("scenes/dam_break.json");
  const std::string sweep = test::sourcePath("bench/sweeps/dam_break.json");
  // 100000 crashed in libgomp, 50000 printed libgomp's raw error.
  for (const std::string& args :
       {"run " + scene + " --threads 100000", "run " + scene + " --threads 50000",
        "run " + scene + " -j -2", "bench " + sweep + " --threads 100000"}) {
    const auto r = runSphsplat(args);
    EXPECT_TRUE(oneShortLine(r)) << args;
    EXPECT_TRUE(std::regex_search(
        r.output, std::regex("^sphsplat: --threads: expected 0 \\(all cores\\) or a thread count "
                             "up to [0-9]+ \\(4 x the [0-9]+ cores here\\), got '")))
        << r.output;
  }
  const std::string file = writeTempFile(R"({"scene": ")" + scene + R"(", "threads": 100000})");
  const auto r = runSphsplat("bench " + file);
  EXPECT_TRUE(oneShortLine(r));
  EXPECT_NE(r.output.find(": threads: expected an integer in [0, "), std::string::npos) << r.output;
}

TEST(Cli, NumericFlagsAreFiniteAndInRangeWithReadableLimits) {
  const std::string scene = test::sourcePath("scenes/dam_break.json");
  // --end nan was accepted and ignored; CLI11's checks printed a 300-digit upper limit.
  for (const std::string end : {"nan", "inf", "1e300", "-1", "0"}) {
    const auto r = runSphsplat("run " + scene + " --end " + end);
    EXPECT_TRUE(oneShortLine(r)) << end;
    EXPECT_EQ(r.output, "sphsplat: --end: expected a number of seconds in (0, 1e6], got '" + end +
                            "' (see sphsplat run --help)\n");
  }
  for (const std::string& args :
       {std::string("view x.h5 --speed nan"), std::string("view x.h5 --exit-after -1"),
        std::string("view x.h5 --width 1e9"), std::string("run")}) {
    EXPECT_TRUE(oneShortLine(runSphsplat(args))) << args;
  }
  const auto r = runSphsplat("run " + scene + " --set output.fps=1e308");
  EXPECT_TRUE(oneShortLine(r));
  EXPECT_NE(r.output.find("output.fps: expected a positive number (frames per simulated second) "
                          "of magnitude at most 1e12, got 1e+308"),
            std::string::npos)
      << r.output;
}

TEST(Cli, ProgressSaysEstimatingUntilTheEtaMeansSomething) {
  // The first line once said "ETA 51m51s" for a 30 s run: extrapolated from the first step.
  // Long enough in wall time (about 4 s here; the ETA needs 2) on a fast machine too.
  const auto r = runSphsplat("run " + test::sourcePath("scenes/dam_break.json") +
                             " --set solver.spacing=0.01 --end 1.2 --threads 2");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::istringstream lines(r.output);
  std::vector<std::string> progress;
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("dam_break ", 0) == 0 && line.find('%') != std::string::npos)
      progress.push_back(line);
  ASSERT_GE(progress.size(), 3u) << r.output;
  EXPECT_NE(progress.front().find("ETA estimating..."), std::string::npos) << progress.front();
  // Once a second of wall time has passed after a second of warm-up, the ETA is a number.
  bool estimated = false;
  for (const std::string& line : progress)
    estimated = estimated || std::regex_search(line, std::regex("ETA [0-9.]+ (s|ms)|ETA [0-9]+m"));
  EXPECT_TRUE(estimated) << r.output;
  EXPECT_NE(progress.back().find("in "), std::string::npos);
}

TEST(Cli, EachSubcommandHelpEndsWithItsOwnFooter) {
  const std::string top = "Run 'sphsplat COMMAND --help'";
  EXPECT_NE(runSphsplat("--help").output.find(top), std::string::npos);
  for (const char* command : {"run", "info", "export", "bench", "render", "compare", "view"}) {
    const auto r = runSphsplat(std::string(command) + " --help");
    EXPECT_EQ(r.exitCode, 0) << command;
    EXPECT_EQ(r.output.find(top), std::string::npos)
        << command << " --help ends with the top-level footer";
  }
  EXPECT_NE(runSphsplat("view --help").output.find("Keys: Space play/pause"), std::string::npos);
}

}  // namespace
}  // namespace sph
