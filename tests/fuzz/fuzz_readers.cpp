// Mutation fuzzer of hexdem's readers: the outline TOML reader and the lattice generator, the
// case-file reader (with the mesh and the solver set-up), the DXF reader, and `hexdem post`
// on .vtu frames. Each input is a seed of the corpus with a few random mutations (bit flips,
// byte and token insertions, deletions, duplications, splices, interesting numbers in place
// of numbers, interesting 64-bit words for binary files). Bad input must end in an
// InputError with a one-line message; anything else is a finding: an internal error (any
// other exception), a multi-line message, a signal or a sanitizer report (under ASan+UBSan
// the sanitizers abort), or a hang (no result after --timeout seconds). Each input runs in a
// child process (fork), so that one crash does not end the run.
//
// Usage: hexdem_fuzz --corpus DIR --work DIR [--seconds S] [--runs N] [--seed K]
//                    [--target outline|case|dxf|vtu|all] [--timeout S]
// Prints one summary line per target; exit 0 without findings, 1 with. Findings are saved
// as WORK/findings/<target>-<n>.<ext>; the input being read is always WORK/input.<ext>.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/outline_dxf.hpp"
#include "hexdem/meshing/outline_toml.hpp"
#include "hexdem/post/post.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem;

/// Few disks: the fuzzer looks for crashes, not for large meshes.
constexpr std::int64_t kFuzzMaxDisks = 3000;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::string mutate(std::string s, const std::vector<std::string>& seeds, bool binary) {
    const int n = 1 + static_cast<int>(pick(4));
    for (int k = 0; k < n; ++k) step(s, seeds, binary);
    if (s.size() > (1u << 22)) s.resize(1u << 22);
    return s;
  }

 private:
  std::mt19937_64 rng_;

  std::uint64_t pick(std::uint64_t n) { return n == 0 ? 0 : rng_() % n; }

  void step(std::string& s, const std::vector<std::string>& seeds, bool binary) {
    static const std::array<const char*, 34> tokens{
        "1e300", "-1e308", "1e-300", "nan", "inf", "-inf", "0", "-1", "-5", "999999999",
        "4000000000", "4294967296", "1e13", "\"", "'", "[", "]", "{", "}", "\n", "=", ".",
        ",", "\\u0000", "\\n", "#", "[[body]]", "\"\"\"", "a.b.c.d.e.f", "<", ">", "</a>",
        "UInt32", "BigEndian"};
    const std::size_t size = s.size();
    switch (pick(binary ? 10 : 9)) {
      case 0:  // flip a bit
        if (size) s[pick(size)] ^= static_cast<char>(1 << pick(8));
        break;
      case 1:  // set a byte
        if (size) s[pick(size)] = static_cast<char>(pick(256));
        break;
      case 2:  // insert a token
        s.insert(pick(size + 1), tokens[pick(tokens.size())]);
        break;
      case 3: {  // delete a range
        if (!size) break;
        const std::size_t at = pick(size);
        s.erase(at, 1 + pick(std::min<std::size_t>(64, size - at)));
        break;
      }
      case 4: {  // duplicate a range
        if (!size) break;
        const std::size_t at = pick(size);
        const std::string part = s.substr(at, 1 + pick(256));
        const int times = 1 + static_cast<int>(pick(8));
        for (int t = 0; t < times; ++t) s.insert(pick(s.size() + 1), part);
        break;
      }
      case 5: {  // replace a number by an interesting one
        std::vector<std::size_t> starts;
        for (std::size_t k = 0; k < size; ++k)
          if ((s[k] >= '0' && s[k] <= '9') && (k == 0 || !(s[k - 1] >= '0' && s[k - 1] <= '9')))
            starts.push_back(k);
        if (starts.empty()) break;
        const std::size_t at = starts[pick(starts.size())];
        std::size_t end = at;
        while (end < size && (std::isdigit(static_cast<unsigned char>(s[end])) || s[end] == '.' || s[end] == 'e' || s[end] == '-'))
          ++end;
        static const std::array<const char*, 14> numbers{
            "0", "-0", "1", "-1", "1e300", "1e-300", "1e308", "nan", "inf", "-5",
            "999999999", "4000000000", "1e13", "2.5"};
        s.replace(at, end - at, numbers[pick(numbers.size())]);
        break;
      }
      case 6: {  // splice with another seed
        if (seeds.empty()) break;
        const std::string& other = seeds[pick(seeds.size())];
        if (other.empty()) break;
        const std::size_t from = pick(other.size());
        s.insert(pick(size + 1), other.substr(from, 1 + pick(512)));
        break;
      }
      case 7:  // truncate
        if (size) s.resize(pick(size));
        break;
      case 8: {  // repeat a line many times (deep or long structures)
        if (!size) break;
        const std::size_t at = pick(size);
        const std::size_t b = s.rfind('\n', at);
        const std::size_t e = s.find('\n', at);
        const std::size_t from = b == std::string::npos ? 0 : b + 1;
        const std::string line = s.substr(from, (e == std::string::npos ? size : e + 1) - from);
        std::string block;
        const int times = 1 + static_cast<int>(pick(300));
        for (int t = 0; t < times; ++t) block += line;
        s.insert(from, block);
        break;
      }
      case 9: {  // an interesting 64-bit word (binary files: headers of appended data)
        if (size < 8) break;
        static const std::array<std::uint64_t, 9> words{
            0, 1, 2, 0xffffffffULL, 0x100000000ULL, 1ULL << 40, ~0ULL, 0x7fffffffffffffffULL, 65536};
        const std::uint64_t w = words[pick(words.size())];
        // Prefer the appended data: header words sit right after the '_' marker.
        std::size_t at = pick(size - 7);
        const std::size_t marker = s.find("<AppendedData");
        if (marker != std::string::npos && pick(2) == 0) {
          const std::size_t data = s.find('_', marker);
          if (data != std::string::npos && data + 9 < size) at = data + 1 + 8 * pick(std::min<std::size_t>(8, (size - data - 9) / 8 + 1));
          if (at + 8 > size) at = size - 8;
        }
        for (int k = 0; k < 8; ++k) s[at + k] = static_cast<char>((w >> (8 * k)) & 0xff);
        break;
      }
    }
  }
};

struct Target {
  std::string name;
  std::string extension;
  bool binary = false;
  std::vector<std::string> seeds;
  std::int64_t runs = 0, input_errors = 0, accepted = 0, findings = 0;
};

enum class Outcome { Accepted, InputError, Finding };

Outcome run_one(const Target& t, const fs::path& input, const fs::path& work, std::size_t k,
                std::string& why) {
  try {
    if (t.name == "outline") {
      meshing::ReadOptions ro;
      const meshing::Outline o = meshing::read_outline_toml(input.string(), ro);
      meshing::GeneratorOptions go;
      go.max_disks = kFuzzMaxDisks;
      (void)meshing::generate_lattice(o, go);
    } else if (t.name == "case") {
      solver::Case c = solver::read_case(input.string());
      c.max_disks = std::min(c.max_disks, kFuzzMaxDisks);
      const meshing::Lattice lattice = solver::mesh_case(c);
      const solver::Solver s(c, lattice);
      (void)s.dt();
    } else if (t.name == "dxf") {
      meshing::ReadOptions ro;
      ro.radius = 0.5e-3;
      const meshing::Outline o = meshing::read_outline_dxf(input.string(), ro);
      meshing::GeneratorOptions go;
      go.max_disks = kFuzzMaxDisks;
      (void)meshing::generate_lattice(o, go);
    } else {
      post::PostOptions po;
      po.analysis = static_cast<post::Analysis>(k % 3);
      po.input = input.string();
      po.output = (work / "post_out").string();
      po.quiet = true;
      std::ostringstream out, err;
      (void)post::run_post(po, out, err);
    }
    return Outcome::Accepted;
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find('\n') != std::string::npos || what.find('\r') != std::string::npos) {
      why = "multi-line message: " + what;
      return Outcome::Finding;
    }
    if (what.empty()) {
      why = "empty message";
      return Outcome::Finding;
    }
    return Outcome::InputError;
  } catch (const std::bad_alloc&) {
    why = "std::bad_alloc";
    return Outcome::Finding;
  } catch (const std::exception& e) {
    why = std::string("internal error: ") + e.what();
    return Outcome::Finding;
  }
}

/// Runs one input in a child process: its exit code carries the outcome, its stderr (a
/// file) the reason; a signal, a sanitizer's abort or a timeout is a finding.
Outcome run_in_child(const Target& t, const fs::path& input, const fs::path& work, std::size_t k,
                     unsigned timeout, std::string& why) {
  const fs::path report = work / "child_report.txt";
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) {
    why = "fork failed";
    return Outcome::Finding;
  }
  if (pid == 0) {
    std::string reason;
    const Outcome o = run_one(t, input, work, k, reason);
    write_file(report, reason);
    _exit(o == Outcome::Accepted ? 0 : o == Outcome::InputError ? 3 : 4);
  }
  int status = 0;
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (std::chrono::steady_clock::now() - start > std::chrono::seconds(timeout)) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      why = "hang (no result after " + std::to_string(timeout) + " s)";
      return Outcome::Finding;
    }
    usleep(200);
  }
  if (WIFSIGNALED(status)) {
    why = "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) +
          "; a sanitizer report, if any, is above)";
    return Outcome::Finding;
  }
  const int code = WEXITSTATUS(status);
  if (code == 0) return Outcome::Accepted;
  if (code == 3) return Outcome::InputError;
  why = code == 4 ? read_file(report) : "exit code " + std::to_string(code) + " (a sanitizer report?)";
  return Outcome::Finding;
}

int usage() {
  std::cerr << "usage: hexdem_fuzz --corpus DIR --work DIR [--seconds S] [--runs N] [--seed K] "
               "[--target outline|case|dxf|vtu|all] [--timeout S]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{{"--seconds", "0"}, {"--runs", "0"}, {"--seed", "1"},
                                          {"--target", "all"}, {"--timeout", "30"}};
  for (int k = 1; k + 1 < argc; k += 2) args[argv[k]] = argv[k + 1];
  if ((argc - 1) % 2 != 0 || !args.count("--corpus") || !args.count("--work")) return usage();
  const fs::path corpus = args["--corpus"], work = args["--work"];
  const double seconds = std::stod(args["--seconds"]);
  const std::int64_t runs = std::stoll(args["--runs"]);
  const unsigned timeout = static_cast<unsigned>(std::stoul(args["--timeout"]));
  if (seconds <= 0 && runs <= 0) return usage();
  fs::create_directories(work / "findings");

  std::vector<Target> targets;
  for (const auto& [name, ext, binary] :
       std::vector<std::tuple<std::string, std::string, bool>>{
           {"outline", ".toml", false}, {"case", ".toml", false}, {"dxf", ".dxf", false}, {"vtu", ".vtu", true}}) {
    if (args["--target"] != "all" && args["--target"] != name) continue;
    Target t{name, ext, binary, {}};
    for (const auto& e : fs::directory_iterator(corpus / name))
      if (e.path().extension() == ext) t.seeds.push_back(read_file(e.path()));
    if (t.seeds.empty()) {
      std::cerr << "hexdem_fuzz: no seeds in " << (corpus / name) << "\n";
      return 2;
    }
    targets.push_back(std::move(t));
  }
  if (targets.empty()) return usage();

  // A case's outline file and frames of a series are found next to the input.
  for (const auto& e : fs::directory_iterator(corpus / "case"))
    if (e.path().extension() != ".toml") fs::copy_file(e.path(), work / e.path().filename(), fs::copy_options::overwrite_existing);

  Mutator mutator(std::stoull(args["--seed"]));
  const auto start = std::chrono::steady_clock::now();
  std::int64_t total = 0;
  for (std::size_t k = 0;; ++k) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (runs > 0 && total >= runs) break;
    if (runs <= 0 && elapsed >= seconds) break;
    Target& t = targets[k % targets.size()];
    const std::string& seed = t.seeds[k / targets.size() % t.seeds.size()];
    // One input in 8 is a seed as it is: the seeds themselves must read.
    const std::string text = (k / targets.size()) % 8 == 0 ? seed : mutator.mutate(seed, t.seeds, t.binary);
    const fs::path input = work / ("input" + t.extension);
    write_file(input, text);
    std::string why;
    const Outcome outcome = run_in_child(t, input, work, k, timeout, why);
    ++t.runs;
    ++total;
    if (outcome == Outcome::Accepted) ++t.accepted;
    if (outcome == Outcome::InputError) ++t.input_errors;
    if (outcome == Outcome::Finding) {
      const fs::path saved = work / "findings" / (t.name + "-" + std::to_string(t.findings) + t.extension);
      fs::copy_file(input, saved, fs::copy_options::overwrite_existing);
      std::cerr << "hexdem_fuzz: FINDING " << t.name << " " << saved.string() << ": " << why << "\n";
      ++t.findings;
    }
  }
  std::int64_t findings = 0;
  for (const Target& t : targets) {
    std::printf("hexdem_fuzz: %-7s %6lld inputs: %6lld accepted, %6lld input errors, %lld findings\n",
                t.name.c_str(), static_cast<long long>(t.runs), static_cast<long long>(t.accepted),
                static_cast<long long>(t.input_errors), static_cast<long long>(t.findings));
    findings += t.findings;
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("hexdem_fuzz: %lld inputs in %.1f s, %lld findings\n", static_cast<long long>(total), elapsed,
              static_cast<long long>(findings));
  return findings == 0 ? 0 : 1;
}
