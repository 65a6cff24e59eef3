// End-to-end tests of `hexdem bench`: it runs for both shear models, with failure and
// contacts, and ends with three parseable figures; bad arguments exit 2 with one line.
// Speeds are never checked against targets here (docs/benchmarks.md measures them).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem::testing;

fs::path work_dir() { return test_dir("cli_bench", true); }

/// The output's lines.
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// The number after `label` on `line`, which must be exactly "LABEL NUMBER"; NaN otherwise.
double figure(const std::string& line, const std::string& label) {
  if (line.rfind(label + " ", 0) != 0) return NAN;
  const std::string value = line.substr(label.size() + 1);
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  return end == value.c_str() + value.size() && !value.empty() ? v : NAN;
}

/// Runs a small bench and checks the contract of its last three lines.
void expect_figures(const std::string& options) {
  const fs::path d = work_dir();
  const Result r = run_hexdem(d, "bench --disks 2000 --steps 20 --threads 1 " + options);
  ASSERT_EQ(r.code, 0) << options << ": " << r.err << r.out;
  EXPECT_EQ(r.err, "") << options;
  const std::vector<std::string> out = lines(r.out);
  ASSERT_GE(out.size(), 4U) << r.out;
  const std::size_t n = out.size();
  const char* labels[] = {"particle-steps/s:", "bond-steps/s:", "peak bytes/disk:"};
  for (std::size_t k = 0; k < 3; ++k) {
    const double v = figure(out[n - 3 + k], labels[k]);
    EXPECT_TRUE(std::isfinite(v) && v > 0) << options << ": '" << out[n - 3 + k] << "'";
  }
  // The informative lines name the set-up.
  EXPECT_NE(r.out.find("disks "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bonds "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("threads 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("set-up time"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("step time"), std::string::npos) << r.out;
}

TEST(BenchCli, Help) {
  const Result r = run_hexdem(work_dir(), "bench --help");
  EXPECT_EQ(r.code, 0);
  for (const char* option : {"--disks", "--model", "--failure", "--softening", "--contacts", "--steps", "--threads", "--order"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

TEST(BenchCli, RotationModel) { expect_figures("--model rotation"); }

TEST(BenchCli, LocalStrainModel) { expect_figures("--model local-strain"); }

TEST(BenchCli, HilbertOrder) {
  expect_figures("--model rotation --order hilbert");
  const Result r = run_hexdem(work_dir(), "bench --disks 2000 --steps 20 --order hilbert");
  EXPECT_NE(r.out.find("disk order Hilbert curve"), std::string::npos) << r.out;
}

TEST(BenchCli, RotationWithFailureAndContacts) { expect_figures("--model rotation --failure --contacts"); }

TEST(BenchCli, LocalStrainWithFailureAndContacts) {
  const fs::path d = work_dir();
  expect_figures("--model local-strain --failure --contacts");
  const Result r = run_hexdem(d, "bench --disks 2000 --steps 20 --threads 1 --failure --contacts");
  EXPECT_NE(r.out.find("failure on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("contacts on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("broken bonds 0,"), std::string::npos) << "the strengths are above the block's stresses: " << r.out;
}

TEST(BenchCli, SofteningWithContacts) {
  // The softening law's bond pass: the bound skips the checks, nothing cracks in the block.
  expect_figures("--model local-strain --failure --softening --contacts");
  const Result r = run_hexdem(work_dir(), "bench --disks 2000 --steps 20 --threads 1 --failure --softening --contacts");
  EXPECT_NE(r.out.find("failure on, softening"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("broken bonds 0,"), std::string::npos) << r.out;
  // The crack state lives in the failed bonds' rows (none here), not in arrays per bond.
  EXPECT_NE(r.out.find("model.failed_row "), std::string::npos) << r.out;
  for (const char* per_bond : {"model.damage", "model.kappa", "model.delta0", "model.delta_f", "model.cracking"})
    EXPECT_EQ(r.out.find(per_bond), std::string::npos) << per_bond << " is stored per bond: " << r.out;
}

TEST(BenchCli, BadArgumentsExit2WithOneLine) {
  const fs::path d = work_dir();
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"--disks 5 --steps 1", {"--disks", "5"}},
      {"--disks 2e9 --steps 1", {"--disks", "2e9"}},
      {"--disks 5e8 --steps 1", {"--disks", "5e8", "3e8"}},  // past the 2^30 bonds a model holds
      {"--disks many --steps 1", {"--disks", "many"}},
      {"--disks 2000 --steps 0", {"--steps", "0"}},
      {"--disks 2000 --steps 1 --model spring", {"--model", "spring"}},
      {"--disks 2000 --steps 1 --threads 0", {"--threads", "0"}},
      {"--disks 2000 --steps 1 --order morton", {"--order", "morton", "hilbert"}},
      {"--disks 2000 --steps 1 --threads 2000", {"--threads", "2000", "1024"}},
      {"--disks 2000 --steps 1 --softening", {"--softening", "--failure"}},
  };
  for (const auto& [args, needles] : cases) {
    const Result r = run_hexdem(d, "bench " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("hexdem: error: ", 0), 0U) << r.err;
    for (const std::string& s : needles) EXPECT_NE(r.err.find(s), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
  }
}

}  // namespace
