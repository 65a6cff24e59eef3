#pragma once
// Running the hexdem program from GoogleTest: exit code, stdout and stderr, in a folder per
// test so that tests can run in parallel.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace hexdem::testing {

namespace fs = std::filesystem;

struct Result {
  int code = -1;     ///< exit code (-1: killed by a signal)
  std::string out;   ///< stdout
  std::string err;   ///< stderr
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// HEXDEM_TEST_WORK_DIR/<group>/<current test name>, created (and emptied if `fresh`).
inline fs::path test_dir(const std::string& group, bool fresh) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path d = fs::path(HEXDEM_TEST_WORK_DIR) / group / info->name();
  if (fresh) fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Runs `hexdem ARGS` with its output captured in files of `dir`.
inline Result run_hexdem(const fs::path& dir, const std::string& args) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = std::string(HEXDEM_BINARY) + " " + args + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace hexdem::testing
