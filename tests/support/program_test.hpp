// Test support shared by every test that runs the built `ricochet` program (RICOCHET_EXE, set by
// CMake; the environment variable RICOCHET_TEST_EXE overrides it, e.g. tests/cli's nodeps run
// against a program built without LIGGGHTS): a per-test temporary directory, and a runner
// capturing stdout, stderr and the exit code. Not a GoogleTest module of its own: tests/<module>/
// include it as "support/...".
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/temp_dir_test.hpp"

namespace ricochet::test {

struct RunResult {
  int status = -1;
  std::string out, err;
};

inline std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The program the tests run: $RICOCHET_TEST_EXE, else RICOCHET_EXE.
inline std::string program() {
  const char* env = std::getenv("RICOCHET_TEST_EXE");
  return env && *env ? env : RICOCHET_EXE;
}

#ifdef RICOCHET_HAVE_LIGGGHTS
// Whether that program has the LIGGGHTS subcommands: $RICOCHET_TEST_HAVE_LIGGGHTS (0 or 1), else
// the build's RICOCHET_HAVE_LIGGGHTS.
inline bool program_has_liggghts() {
  const char* env = std::getenv("RICOCHET_TEST_HAVE_LIGGGHTS");
  return env && *env ? std::string(env) != "0" : RICOCHET_HAVE_LIGGGHTS != 0;
}
#endif

// Whether the arguments run a subcommand of the resolved model (dem, upscale, calibrate-grains),
// which needs LIGGGHTS.
inline bool needs_liggghts(const std::string& args) {
  for (const char* sub : {"dem", "upscale", "calibrate-grains"})
    if (args == sub || args.rfind(std::string(sub) + " ", 0) == 0) return true;
  return false;
}

class ProgramTest : public TempDirTest {
 protected:
  ProgramTest() : TempDirTest("ricochet-cmd") {}

  // Runs `ricochet ARGS` (ARGS already shell-quoted).
  RunResult ricochet(const std::string& args) const {
    const auto err = dir_ / "stderr.txt";
    const std::string cmd = quote(program()) + " " + args + " 2>" + quote(err.string());
    RunResult run;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) return run;
    std::array<char, 4096> buf;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) run.out.append(buf.data(), n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.err = slurp(err);
    return run;
  }
};

}  // namespace ricochet::test
