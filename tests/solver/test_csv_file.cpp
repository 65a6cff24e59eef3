// CsvFile's layout (docs/file-format.md, "Output"): no row straddles a 4 KiB page of the file,
// so that a killed run (Linux stops a killed write() only at a page boundary) leaves whole
// rows. The kill itself is exercised end to end by HostileCli.KillNine...; this test checks
// the layout that makes it safe, deterministically, for files far longer than a kill test
// writes, including a restart that appends.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hexdem/solver/output.hpp"

namespace fs = std::filesystem;
using hexdem::solver::CsvFile;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hexdem_csv_file_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

/// One row as RunOutput writes it: time, step, then %.10g numbers of every length.
std::string make_row(std::mt19937_64& rng, long long step, int values) {
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300), kind(0, 3);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", 1e-6 * static_cast<double>(step));
  std::string row(buf);
  row += ',';
  row += std::to_string(step);
  for (int k = 0; k < values; ++k) {
    const int which = kind(rng);
    const double v = which == 0 ? 0.0 : which == 1 ? 0.5 : mantissa(rng) * std::pow(10.0, exponent(rng));
    std::snprintf(buf, sizeof buf, "%.10g", v);
    row += ',';
    row += buf;
  }
  row += '\n';
  return row;
}

/// The rows of the file with their leading blanks removed.
std::vector<std::string> rows_of(const std::string& text) {
  std::vector<std::string> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) rows.push_back(line.substr(line.find_first_not_of(' ')) + "\n");
  return rows;
}

/// Every 4 KiB boundary inside the file falls just after a newline.
void expect_no_row_straddles_a_page(const std::string& text) {
  for (std::size_t b = CsvFile::kPage; b < text.size(); b += CsvFile::kPage)
    EXPECT_EQ(text[b - 1], '\n') << "a row straddles the page boundary at byte " << b;
}

TEST(CsvFile, NoRowStraddlesAPageAndTheRowsReadBackUnchanged) {
  const fs::path path = scratch("rows.csv");
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> batch(1, 7);
  std::vector<std::string> expected;
  std::string header = "time,step";
  for (int k = 0; k < 12; ++k) header += ",value_" + std::to_string(k);
  header += "\n";
  expected.push_back(header);
  {
    CsvFile f;
    f.open(path.string());
    f << header;
    long long step = 0;
    while (step < 4000) {
      for (int n = batch(rng); n > 0; --n) {
        expected.push_back(make_row(rng, step++, 12));
        f << expected.back();
      }
      f.flush();
    }
    EXPECT_TRUE(f.rows_fit_pages());
    f.close();
  }
  const std::string text = slurp(path);
  ASSERT_GT(text.size(), 50 * CsvFile::kPage);  // the check below covers dozens of boundaries
  expect_no_row_straddles_a_page(text);
  EXPECT_EQ(rows_of(text), expected);
  // The padding is what the layout needs, not a doubling of the file.
  std::size_t payload = 0;
  for (const std::string& r : expected) payload += r.size();
  EXPECT_LT(static_cast<double>(text.size()), 1.25 * static_cast<double>(payload));
  fs::remove_all(path.parent_path());
}

TEST(CsvFile, ARestartThatAppendsKeepsTheLayout) {
  const fs::path path = scratch("restart.csv");
  std::mt19937_64 rng(11);
  std::vector<std::string> expected = {"time,step,a,b,c,d,e\n"};
  long long step = 0;
  for (int run = 0; run < 3; ++run) {
    CsvFile f;
    f.open(path.string(), run > 0);
    if (run == 0) f << expected.front();
    for (int k = 0; k < 700; ++k) {
      expected.push_back(make_row(rng, step++, 5));
      f << expected.back();
      if (k % 3 == 0) f.flush();
    }
    f.close();
  }
  const std::string text = slurp(path);
  expect_no_row_straddles_a_page(text);
  EXPECT_EQ(rows_of(text), expected);
  fs::remove_all(path.parent_path());
}

TEST(CsvFile, AnUnfinishedRowWaitsForItsEnd) {
  const fs::path path = scratch("partial.csv");
  CsvFile f;
  f.open(path.string());
  f << "time,step\n" << "1.5";
  f.flush();
  EXPECT_EQ(slurp(path), "time,step\n");
  f << ",3\n";
  f.flush();
  EXPECT_EQ(slurp(path), "time,step\n1.5,3\n");
  f.close();
  fs::remove_all(path.parent_path());
}

TEST(CsvFile, AFileTooWideForTheLayoutIsWrittenUnpadded) {
  // 150 columns: a row can be 2.7 KiB, more than half a page; padding would waste pages.
  const fs::path path = scratch("wide.csv");
  std::mt19937_64 rng(3);
  std::string header = "time,step";
  for (int k = 0; k < 148; ++k) header += ",v" + std::to_string(k);
  header += "\n";
  std::string all = header;
  CsvFile f;
  f.open(path.string());
  f << header;
  for (long long step = 0; step < 40; ++step) {
    const std::string row = make_row(rng, step, 148);
    all += row;
    f << row;
    f.flush();
  }
  EXPECT_FALSE(f.rows_fit_pages());
  f.close();
  EXPECT_EQ(slurp(path), all);
  fs::remove_all(path.parent_path());
}

}  // namespace
