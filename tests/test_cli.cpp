// The sphsplat binary as a user meets it: help, version, bad scenes and flags refused with one
// line and exit code 2, a run with its summary, and the blow-up guard's message and exit code 3.
#include <gtest/gtest.h>

#include <regex>

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
       "solver.spacing: expected a positive number (m), got -0.01"},
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
  EXPECT_NE(badSet.output.find("solver.spacing: expected a positive number (m), got -1"),
            std::string::npos);
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

}  // namespace
}  // namespace sph
