// The collision pass as a user meets it (DESIGN.md, "What a scene does not need is not run"):
// only cdt-gl creates a GL context; without EGL, or with a broken shader, cdt-gl stops the run
// with one line that names the failure (the shader's file and line) and suggests cdt-cpu, while
// every other method runs; a bad collision section is refused with its key path; and a cdt-gl
// run ends in exactly the state of the same cdt-cpu run.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <cstdio>
#include <fstream>

#include <cstdlib>
#include <iterator>

#include "render/cdt/CollisionSetup.h"
#include "render/gl/GlContext.h"
#include "sim/run/Simulation.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using test::runSphsplat;

std::string lastLine(const std::string& s) {
  std::string t = s;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  return t.substr(t.rfind('\n') == std::string::npos ? 0 : t.rfind('\n') + 1);
}

// The shipped rain scene, small: 4,800 particles 3 cm apart, 2 cm above the sphere.
const char* kSmallRain = "--set solver.spacing=0.03 --set fluids[0].min=[-0.3,0.62,-0.3]";

std::string rain() {
  return test::sourcePath("scenes/cdt_rain.json");
}

// Runs sphsplat with extra environment variables ("NAME=value ..."); exit code and output.
test::CommandResult runWithEnvironment(const std::string& environment,
                                       const std::string& arguments) {
  FILE* pipe = popen(
      ("env " + environment + " " + test::sphsplatCommand() + " " + arguments + " 2>&1").c_str(),
      "r");
  test::CommandResult r;
  char buffer[4096];
  std::size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  return r;
}

TEST(CollisionSetup, NoGlContextUnlessTheSceneAsksForCdtGl) {
  const int before = render::gl::GlContext::createdCount();
  // No collision section at all: no pass.
  EXPECT_EQ(render::cdt::makeCollisionPass(test::shippedScene("dam_break")), nullptr);
  for (const char* method : {"none", "exact", "octree", "cdt-cpu"}) {
    scene::Scene scene = test::shippedScene(
        "cdt_rain", {"solver.spacing=0.03", std::string("collision.method=") + method});
    run::Simulation sim(scene);
    sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
    for (int s = 0; s < 3; ++s) sim.step();
    EXPECT_EQ(render::gl::GlContext::createdCount(), before)
        << method << " must not create a GL context";
  }
  {
    scene::Scene scene = test::shippedScene("cdt_rain", {"solver.spacing=0.03"});
    auto pass = render::cdt::makeCollisionPass(scene);
    EXPECT_EQ(pass->name(), "cdt-gl");
    EXPECT_EQ(render::gl::GlContext::createdCount(), before + 1)
        << "cdt-gl makes exactly one context";
    EXPECT_EQ(render::gl::GlContext::liveCount(), 1);
  }
  EXPECT_EQ(render::gl::GlContext::liveCount(), 0);
}

TEST(CollisionCli, VerboseSaysWhatRuns) {
  const auto cpu =
      runSphsplat("run " + rain() + " --end 0.004 -v --set collision.method=cdt-cpu " + kSmallRain);
  EXPECT_EQ(cpu.exitCode, 0) << cpu.output;
  EXPECT_NE(cpu.output.find("collision: cdt-cpu, range 0.01 m, response paper"), std::string::npos)
      << cpu.output;
  EXPECT_NE(cpu.output.find("no GL context"), std::string::npos) << cpu.output;
  const auto none =
      runSphsplat("run " + test::sourcePath("scenes/still_tank.json") + " --end 0.002 -v");
  EXPECT_NE(none.output.find("skipped: collision pass (no collision section)"), std::string::npos)
      << none.output;
}

TEST(CollisionCli, WithoutEglCdtGlStopsWithOneLineAndCdtCpuRuns) {
  const auto gl = runSphsplat("run " + rain() + " --end 0.004 -q " + kSmallRain);
  EXPECT_EQ(gl.exitCode, 0) << "with EGL, cdt-gl runs: " << gl.output;
  // glvnd finds no EGL vendor: as on a machine without EGL drivers.
  const std::string noEgl = "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json";
  const auto r = runWithEnvironment(noEgl, "run " + rain() + " --end 0.004 -q " + kSmallRain);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "exactly one line: " << r.output;
  EXPECT_NE(r.output.find("collision.method: cdt-gl is unavailable: no EGL display"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("cdt-cpu"), std::string::npos) << r.output;
  const auto cpu = runWithEnvironment(
      noEgl, "run " + rain() + " --end 0.004 -q --set collision.method=cdt-cpu " + kSmallRain);
  EXPECT_EQ(cpu.exitCode, 0) << cpu.output;
}

TEST(CollisionCli, BrokenShaderNamesItsFileAndLine) {
  const std::string dir = test::makeTempDirectory("sphsplat-broken");
  for (const char* name : {"cdt_constants.glsl", "cdt_common.glsl", "cdt_collide.vert",
                           "cdt_write.frag", "cdt_write.comp", "cdt_peel.vert"}) {
    std::ifstream in(test::sourcePath(std::string("shaders/") + name));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (std::string(name) == "cdt_common.glsl") {
      // A new line 30 in the included file.
      std::size_t at = 0;
      for (int line = 1; line < 30; ++line) at = text.find('\n', at) + 1;
      text.insert(at, "float broken = notDeclaredAnywhere;\n");
    }
    std::ofstream(dir + "/" + name) << text;
  }
  const auto r = runWithEnvironment("SPHSPLAT_SHADER_DIR=" + dir,
                                    "run " + rain() + " --end 0.004 -q " + kSmallRain);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "exactly one line: " << r.output;
  EXPECT_NE(r.output.find(dir + "/cdt_common.glsl:30:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("notDeclaredAnywhere"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("cdt-cpu"), std::string::npos) << r.output;
}

TEST(CollisionCli, BadCollisionSectionsAreRefusedWithTheKeyPath) {
  const auto bad = runSphsplat("run " + rain() + " --set collision.method=magic");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(lastLine(bad.output).find("collision.method: expected one of \"none\", \"exact\""),
            std::string::npos)
      << bad.output;
  const auto layers = runSphsplat("run " + rain() + " --set collision.layers=9");
  EXPECT_EQ(layers.exitCode, 2);
  EXPECT_NE(lastLine(layers.output).find("collision.layers"), std::string::npos) << layers.output;
  const auto pose = runSphsplat("run " + rain() + " --set collision.camera=fixed");
  EXPECT_EQ(pose.exitCode, 2);
  EXPECT_NE(lastLine(pose.output).find("collision.pose: missing"), std::string::npos)
      << pose.output;
  const auto typo = runSphsplat("run " + rain() + " --set collision.texel_rnage=2");
  EXPECT_NE(lastLine(typo.output).find("did you mean \"texel_range\""), std::string::npos)
      << typo.output;
}

// The CDT's texture stores particle ids as floats, exact below 2^24: a scene that could pass that
// is refused before it runs, naming the key to change (an input limit, exit 2; not an internal
// error mid-run).
TEST(CollisionCli, ScenesThatWouldPassTheTexturesIdRangeAreRefusedBeforeTheRun) {
  // 400 x 160 x 400 lattice points in the rain's block: refused by the loader, before any
  // particle exists.
  const auto blocks =
      runSphsplat("run " + rain() + " --set solver.spacing=0.0015 --set collision.method=cdt-cpu");
  EXPECT_EQ(blocks.exitCode, 2) << blocks.output;
  EXPECT_EQ(blocks.output.find('\n'), blocks.output.size() - 1) << "one line: " << blocks.output;
  EXPECT_NE(blocks.output.find("cdt_rain.json: solver.spacing: the fluid blocks would hold "
                               "25,600,000 particles; the cdt-cpu collision pass handles "
                               "particle ids below 16,777,216"),
            std::string::npos)
      << blocks.output;
  // A nozzle that never stops: the scene's own end time keeps it in range, `--end` does not.
  const std::string pour = test::sourcePath("scenes/pour.json") +
                           " -q --set collision.method=cdt-gl --set emitters[0].stop=1e9";
  const auto emitter = runSphsplat("run " + pour + " --end 1e6");
  EXPECT_EQ(emitter.exitCode, 2) << emitter.output;
  EXPECT_NE(
      emitter.output.find("pour.json: emitters[0].max_particles: the scene would make up to "),
      std::string::npos)
      << emitter.output;
  EXPECT_NE(emitter.output.find("the cdt-gl collision pass handles particle ids below 16,777,216"),
            std::string::npos)
      << emitter.output;
  // The key it names is the way out.
  const auto capped = runSphsplat("run " + pour + " --set emitters[0].max_particles=100000 " +
                                  "--set collision.method=cdt-cpu --end 0.02");
  EXPECT_EQ(capped.exitCode, 0) << capped.output;
}

// End to end through the Simulation: the particle system of the rain scene with cdt-gl ends in
// the very state cdt-cpu reaches (same bits), collisions included.
TEST(CollisionCli, CdtGlRunEqualsCdtCpuRun) {
  auto run = [](const char* method) {
    scene::Scene scene =
        test::shippedScene("cdt_rain", {"solver.spacing=0.03", "fluids[0].min=[-0.3,0.62,-0.3]",
                                        std::string("collision.method=") + method});
    run::Simulation sim(scene);
    sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
    sim.advanceTo(0.16);
    std::size_t cooling = 0;
    for (float t : sim.fluid().collideTime) cooling += t >= 0;
    return std::make_pair(test::stateHash(sim.fluid()), cooling);
  };
  const auto cpu = run("cdt-cpu");
  const auto gl = run("cdt-gl");
  EXPECT_GT(cpu.second, 0u) << "the comparison needs collisions";
  EXPECT_EQ(gl.second, cpu.second);
  EXPECT_EQ(gl.first, cpu.first);
}

}  // namespace
}  // namespace sph
