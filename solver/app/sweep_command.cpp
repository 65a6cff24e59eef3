// `hexdem sweep STUDY.toml`: a parameter study (docs/studies.md). Each member is the case
// with its own --set values, run as a child `hexdem run` in its own folder; the final values
// of the members' `<case>.summary.csv` go into one CSV, one row per member.
#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/meshing/text.hpp"
#include "hexdem/meshing/toml_values.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/output.hpp"
#include "hexdem/solver/run_summary.hpp"
#include "subcommands.hpp"

namespace hexdem::app {
namespace {

namespace fs = std::filesystem;
using meshing::describe;

struct SweepArgs {
  std::string study;
  std::string out;
  bool out_given = false;  ///< -o was given (an empty -o is refused)
  int jobs = 1;
  int threads = 0;
  bool dry_run = false;
  bool collect = false;
  bool quiet = false;
};

struct Parameter {
  std::string key;
  std::vector<std::string> values;  ///< TOML text of each value
};

struct Study {
  std::string name;
  std::string case_file;       ///< absolute
  std::vector<std::string> fixed;  ///< --set for every member
  bool grid = true;
  std::vector<Parameter> parameters;
  std::vector<std::string> outputs;  ///< summary columns to collect (empty: all)
};

struct Member {
  std::vector<std::string> sets;  ///< the member's own KEY=VALUE
  std::string folder;
  std::vector<std::string> argv;  ///< the child's command line
  std::string command;            ///< the same, shell-quoted
  std::string case_name;          ///< the member's own case name (`case.name` may be varied)
  std::vector<std::string> columns;  ///< the columns of its summary
  int exit_code = -1;
};

/// Why `name` cannot be a study name (names `<name>.csv` and `<name>-study`), or "". Spaces
/// are refused in `study.name`, not in the default, the study file's stem.
std::string study_name_problem(const std::string& name, bool spaces_ok) {
  if (name.empty()) return "must not be empty";
  if (name == "." || name == "..") return "must be a plain file name stem, not '.' or '..'";
  if (name.front() == '.') return "must not start with '.' (a hidden file)";
  if (name.find_first_of(spaces_ok ? "/\\" : "/\\ ") != std::string::npos)
    return "must be a plain file name stem, without '/', '\\' or spaces";
  if (meshing::has_control_character(name)) return "must not hold control characters";
  if (name.size() > 200) return "must have at most 200 characters";
  return {};
}

/// TOML text of a value for --set: numbers that read back exactly, strings quoted.
std::string toml_text(const toml::node& v, const std::string& where) {
  if (const auto* i = v.as_integer()) return std::to_string(i->get());
  if (const auto* f = v.as_floating_point()) {
    std::string t = meshing::format_number(f->get());
    if (t.find_first_of(".eEn") == std::string::npos) t += ".0";  // stays a float
    return t;
  }
  if (const auto* b = v.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* s = v.as_string()) {
    std::string out = "\"";
    for (char ch : s->get()) {
      if (ch == '"' || ch == '\\') out += '\\';
      out += ch;
    }
    return out + "\"";
  }
  if (const auto* a = v.as_array()) {
    std::string out = "[";
    for (std::size_t k = 0; k < a->size(); ++k) out += (k ? ", " : "") + toml_text(*a->get(k), where);
    return out + "]";
  }
  throw InputError(where + ": a parameter value must be a number, string, boolean or array (got " + describe(v) + ")");
}

std::string shell_quote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+./=:,") ==
                        std::string::npos)
    return s;
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

/// "FILE:LINE: " for messages about the study file.
std::string at(const std::string& file, const toml::node& n) {
  return file + ":" + std::to_string(n.source().begin.line) + ": ";
}

Study read_study(const std::string& path) {
  const toml::table root = meshing::parse_toml(meshing::read_text_file(path), path);
  for (const auto& [key, node] : root)
    if (key.str() != "study" && key.str() != "parameter")
      throw InputError(path + ":" + std::to_string(key.source().begin.line) + ": unknown key '" + std::string(key.str()) +
                       "' (allowed: study, parameter)");
  const toml::table* st = root["study"].as_table();
  if (st == nullptr) throw InputError(path + ": missing table [study] (with at least `case`)");
  Study s;
  s.name = fs::path(path).stem().string();
  bool named = false;
  for (const auto& [key, node] : *st) {
    const std::string k(key.str());
    const std::string where = at(path, node) + "study." + k;
    auto text = [&]() {
      if (const auto* v = node.as_string()) return v->get();
      throw InputError(where + ": expected a string (got " + describe(node) + ")");
    };
    auto texts = [&]() {
      std::vector<std::string> out;
      const toml::array* a = node.as_array();
      if (a == nullptr) throw InputError(where + ": expected an array of strings (got " + describe(node) + ")");
      for (const toml::node& e : *a) {
        const auto* v = e.as_string();
        if (v == nullptr) throw InputError(where + ": expected an array of strings (got " + describe(e) + ")");
        out.push_back(v->get());
      }
      return out;
    };
    if (k == "case") {
      if (text().empty()) throw InputError(where + ": expected the path of the case file (got \"\")");
      fs::path file(text());
      if (file.is_relative()) file = fs::path(path).parent_path() / file;
      s.case_file = fs::absolute(file).lexically_normal().string();
      if (!std::ifstream(s.case_file))
        throw InputError(where + ": cannot open case file '" + s.case_file + "' (got " + describe(node) + ")");
    } else if (k == "name") {
      s.name = text();
      named = true;
      if (const std::string problem = study_name_problem(s.name, false); !problem.empty())
        throw InputError(where + ": " + problem + " (got " + describe(node) + ")");
    } else if (k == "combine") {
      const std::string c = text();
      if (c != "grid" && c != "list")
        throw InputError(where + ": expected \"grid\" (every combination) or \"list\" (the k-th value of each) (got " +
                         describe(node) + ")");
      s.grid = c == "grid";
    } else if (k == "set") {
      s.fixed = texts();
      for (const std::string& f : s.fixed)
        if (f.find('=') == std::string::npos) throw InputError(where + ": expected KEY=VALUE entries (got \"" + f + "\")");
    } else if (k == "outputs") {
      s.outputs = texts();
    } else {
      throw InputError(where + ": unknown key '" + k + "' (allowed: case, name, combine, set, outputs)");
    }
  }
  if (s.case_file.empty()) throw InputError(path + ": [study]: missing key 'case'");
  if (!named)
    if (const std::string problem = study_name_problem(s.name, true); !problem.empty())
      throw InputError(path + ": [study]: the study file's stem \"" + meshing::escape_text(s.name) +
                       "\" does not make a study name: it " + problem + " (give study.name)");

  const toml::node* params = root.get("parameter");
  const toml::array* list = params != nullptr ? params->as_array() : nullptr;
  if (list == nullptr || list->empty() || !list->is_array_of_tables())
    throw InputError(path + ": expected [[parameter]] tables (each a key and its values)");
  for (std::size_t p = 0; p < list->size(); ++p) {
    const toml::table& t = *list->get(p)->as_table();
    const std::string base = "parameter[" + std::to_string(p) + "]";
    Parameter par;
    const toml::node *values = nullptr, *from = nullptr, *to = nullptr, *count = nullptr;
    for (const auto& [key, node] : t) {
      const std::string k(key.str());
      const std::string where = at(path, node) + base + "." + k;
      if (k == "key") {
        const auto* v = node.as_string();
        if (v == nullptr || v->get().empty() || v->get().find('=') != std::string::npos)
          throw InputError(where + ": expected a dotted case key, e.g. \"material.1.E\" (got " + describe(node) + ")");
        par.key = v->get();
      } else if (k == "values") {
        values = &node;
      } else if (k == "from") {
        from = &node;
      } else if (k == "to") {
        to = &node;
      } else if (k == "count") {
        count = &node;
      } else {
        throw InputError(where + ": unknown key '" + k + "' (allowed: key, values, or from, to, count)");
      }
    }
    const std::string where = at(path, t) + base;
    if (par.key.empty()) throw InputError(where + ": missing key 'key'");
    for (const Parameter& other : s.parameters)
      if (other.key == par.key) throw InputError(where + ".key: \"" + par.key + "\" is varied twice");
    if (values != nullptr) {
      if (from || to || count) throw InputError(where + ": give either values or from, to and count");
      const toml::array* a = values->as_array();
      if (a == nullptr || a->empty())
        throw InputError(where + ".values: expected a non-empty array (got " + describe(*values) + ")");
      for (const toml::node& v : *a) par.values.push_back(toml_text(v, where + ".values"));
    } else {
      if (!from || !to || !count) throw InputError(where + ": give values, or from, to and count");
      const meshing::TomlValues reader(path);
      const double lo = reader.number(*from, base + ".from"), hi = reader.number(*to, base + ".to");
      const auto* n = count->as_integer();
      if (n == nullptr || n->get() < 2 || n->get() > 100000)
        throw InputError(at(path, *count) + base + ".count: expected an integer from 2 to 100000 (got " +
                         describe(*count) + ")");
      for (std::int64_t k = 0; k < n->get(); ++k) {
        const double v = lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(n->get() - 1);
        par.values.push_back(toml_text(toml::value<double>(k + 1 == n->get() ? hi : v), where));
      }
    }
    s.parameters.push_back(std::move(par));
  }
  if (!s.grid) {
    for (const Parameter& p : s.parameters)
      if (p.values.size() != s.parameters[0].values.size())
        throw InputError(path + ": combine = \"list\" needs as many values for every parameter (" + s.parameters[0].key +
                         ": " + std::to_string(s.parameters[0].values.size()) + ", " + p.key + ": " +
                         std::to_string(p.values.size()) + ")");
  }
  return s;
}

std::vector<std::vector<std::string>> member_sets(const Study& s) {
  std::vector<std::vector<std::string>> out;
  if (!s.grid) {
    for (std::size_t k = 0; k < s.parameters[0].values.size(); ++k) {
      std::vector<std::string> m;
      for (const Parameter& p : s.parameters) m.push_back(p.key + "=" + p.values[k]);
      out.push_back(std::move(m));
    }
    return out;
  }
  std::size_t total = 1;
  for (const Parameter& p : s.parameters) {
    total *= p.values.size();
    if (total > 100000) throw InputError("study: more than 100000 members in the grid");
  }
  for (std::size_t k = 0; k < total; ++k) {
    // The last parameter varies fastest.
    std::vector<std::string> m(s.parameters.size());
    std::size_t rest = k;
    for (std::size_t p = s.parameters.size(); p-- > 0;) {
      const Parameter& par = s.parameters[p];
      m[p] = par.key + "=" + par.values[rest % par.values.size()];
      rest /= par.values.size();
    }
    out.push_back(std::move(m));
  }
  return out;
}

std::string self_exe() {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) throw std::runtime_error("cannot find the hexdem program (/proc/self/exe)");
  return std::string(buf, static_cast<std::size_t>(n));
}

// ---- signals ------------------------------------------------------------------------------
// SIGINT, SIGTERM or SIGHUP to the sweep is forwarded to the running members, each in its own
// process group (so that a terminal's Ctrl-C reaches a member once, through the sweep). They
// stop (a run records `interrupted` and exits 128 + the signal), the sweep records their exit
// codes, starts no other member, writes the table and ends by the same signal.

volatile std::sig_atomic_t g_sweep_signal = 0;
pid_t* g_member_pids = nullptr;  ///< running members (0: a free slot), changed with the signals blocked
std::size_t g_member_slots = 0;

extern "C" void forward_signal(int sig) {
  g_sweep_signal = sig;
  for (std::size_t k = 0; k < g_member_slots; ++k)
    if (g_member_pids[k] > 0) ::kill(g_member_pids[k], sig);
}

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};

sigset_t stop_signal_set() {
  sigset_t set;
  sigemptyset(&set);
  for (int sig : kStopSignals) sigaddset(&set, sig);
  return set;
}

/// The stop signals blocked in a scope (pending ones are delivered at its end).
class BlockStopSignals {
 public:
  BlockStopSignals() {
    const sigset_t set = stop_signal_set();
    ::sigprocmask(SIG_BLOCK, &set, &old_);
  }
  ~BlockStopSignals() { ::sigprocmask(SIG_SETMASK, &old_, nullptr); }
  BlockStopSignals(const BlockStopSignals&) = delete;
  BlockStopSignals& operator=(const BlockStopSignals&) = delete;

 private:
  sigset_t old_;
};

/// Installs forward_signal while members run (a signal ignored at start, as under nohup,
/// stays ignored) and restores the previous handlers after.
class ForwardStopSignals {
 public:
  explicit ForwardStopSignals(std::size_t slots) : pids_(slots, 0) {
    const BlockStopSignals blocked;
    g_sweep_signal = 0;
    g_member_pids = pids_.data();
    g_member_slots = pids_.size();
    for (std::size_t k = 0; k < std::size(kStopSignals); ++k) {
      ::sigaction(kStopSignals[k], nullptr, &saved_[k]);
      if (saved_[k].sa_handler == SIG_IGN) continue;
      struct sigaction sa {};
      sa.sa_handler = forward_signal;
      sa.sa_mask = stop_signal_set();
      sa.sa_flags = 0;  // no SA_RESTART: the wait for a member returns EINTR
      ::sigaction(kStopSignals[k], &sa, nullptr);
    }
  }
  ~ForwardStopSignals() {
    const BlockStopSignals blocked;
    for (std::size_t k = 0; k < std::size(kStopSignals); ++k) ::sigaction(kStopSignals[k], &saved_[k], nullptr);
    g_member_pids = nullptr;
    g_member_slots = 0;
  }
  ForwardStopSignals(const ForwardStopSignals&) = delete;
  ForwardStopSignals& operator=(const ForwardStopSignals&) = delete;

  /// With the stop signals blocked.
  void add(pid_t pid) { *std::find(pids_.begin(), pids_.end(), 0) = pid; }
  void remove(pid_t pid) { std::replace(pids_.begin(), pids_.end(), pid, 0); }

 private:
  std::vector<pid_t> pids_;
  struct sigaction saved_[std::size(kStopSignals)] {};
};

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

/// Whether an exit code 128 + N (as a shell reports a process killed by signal N) is a crash:
/// an internal error of the member, as exit code 1.
bool crashed(int code) {
  if (code <= 128 || code > 128 + 64) return false;
  const int sig = code - 128;
  return sig == SIGSEGV || sig == SIGABRT || sig == SIGBUS || sig == SIGFPE || sig == SIGILL || sig == SIGSYS ||
         sig == SIGTRAP;
}

/// Starts the member's run in its own process group (call with the stop signals blocked);
/// -1 and `error` if it cannot start.
pid_t spawn(const Member& m, std::string& error) {
  const std::string log = (fs::path(m.folder) / "run.log").string();
  std::vector<char*> argv;
  for (const std::string& a : m.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    error = fs::path(m.folder).filename().string() + ": cannot start the member's run (" + std::strerror(errno) + ")";
    return -1;
  }
  if (pid == 0) {
    ::setpgid(0, 0);
    const sigset_t set = stop_signal_set();
    ::sigprocmask(SIG_UNBLOCK, &set, nullptr);
    const int in = ::open("/dev/null", O_RDONLY);
    if (in >= 0) {
      ::dup2(in, 0);
      ::close(in);
    }
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
      ::dprintf(2, "hexdem sweep: %s: cannot write (%s)\n", meshing::escape_text(log).c_str(), std::strerror(errno));
      _exit(127);
    }
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::close(fd);
    ::execv(argv[0], argv.data());
    _exit(127);
  }
  ::setpgid(pid, pid);  // also here: the member is in its group before a signal is forwarded
  return pid;
}

/// The fields of one CSV line (double quotes and "" escapes as the table writes them).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char ch = line[k];
    if (quoted) {
      if (ch == '"' && k + 1 < line.size() && line[k + 1] == '"') {
        out.back() += '"';
        ++k;
      } else if (ch == '"') {
        quoted = false;
      } else {
        out.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  return out;
}

/// `text` as one CSV field (quoted when it holds a comma or a double quote).
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string q = "\"";
  for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

/// The row of `file`, a member's summary CSV, as column -> text: its header must be
/// `columns` and its one row a number for each. Empty, and `problem` says why, otherwise.
std::map<std::string, std::string> read_summary(const fs::path& file, const std::vector<std::string>& columns,
                                                std::string& problem) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    problem = "is missing";
    return {};
  }
  std::ifstream in(file, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) {
    problem = "cannot be read";
    return {};
  }
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string l; std::getline(s, l);) lines.push_back(l);
  if (lines.size() != 2 || text.back() != '\n') {
    problem = lines.size() < 2 ? "has no row of values" : "is not one header and one row";
    return {};
  }
  const std::vector<std::string> header = csv_fields(lines[0]), row = csv_fields(lines[1]);
  if (header != columns) {
    problem = "has other columns than the member's case gives";
    return {};
  }
  if (row.size() != header.size()) {
    problem = "has " + std::to_string(row.size()) + " values for " + std::to_string(header.size()) + " columns";
    return {};
  }
  std::map<std::string, std::string> out;
  for (std::size_t k = 0; k < header.size(); ++k) {
    char* end = nullptr;
    std::strtod(row[k].c_str(), &end);
    if (row[k].empty() || *end != '\0') {
      problem = "has a value that is not a number (" + header[k] + ")";
      return {};
    }
    out[header[k]] = row[k];
  }
  return out;
}

/// The files of a member's previous run that the sweep reads or that tell how it ended: removed
/// before the member runs again, so that a member refused at set-up has no stale values.
std::vector<std::string> previous_outputs(const Member& m) {
  return {"exit_code", m.case_name + ".summary.csv", m.case_name + ".status", m.case_name + ".case.toml"};
}

int run_sweep(const SweepArgs& a) {
  const Study study = read_study(a.study);
  const std::vector<std::vector<std::string>> sets = member_sets(study);
  if (a.out_given && a.out.empty()) throw InputError("-o: expected an output folder (got \"\")");
  // Absolute, so that the written command lines run from any folder.
  const std::string out_dir = fs::absolute(a.out.empty() ? study.name + "-study" : a.out).lexically_normal().string();

  // Every member's case is read (with its overrides) before anything runs: a bad value
  // stops the study with the case reader's message. Each member has its own case name (a
  // study may vary `case.name`) and the summary columns of its bodies.
  std::vector<Member> members(sets.size());
  for (std::size_t k = 0; k < sets.size(); ++k) {
    std::vector<std::string> all = study.fixed;
    all.insert(all.end(), sets[k].begin(), sets[k].end());
    try {
      const solver::Case c = solver::read_case(study.case_file, all);
      std::vector<std::string> bodies;
      for (const auto& b : c.outline.bodies) bodies.push_back(b.name);
      members[k].case_name = c.name;
      members[k].columns = solver::run_summary_columns(bodies);
    } catch (const InputError& e) {
      throw InputError(a.study + ": member " + std::to_string(k + 1) + ": " + e.what());
    }
  }
  const std::vector<std::string>& columns = members[0].columns;
  std::vector<std::string> outputs = study.outputs.empty() ? columns : study.outputs;
  for (const std::string& o : outputs)
    if (std::find(columns.begin(), columns.end(), o) == columns.end()) {
      std::string list;
      for (const std::string& c : columns) list += (list.empty() ? "" : ", ") + c;
      throw InputError(a.study + ": study.outputs: unknown output '" + o + "' (outputs: " + list + ")");
    }
  for (std::size_t k = 1; k < members.size(); ++k)
    for (const std::string& o : outputs)
      if (std::find(members[k].columns.begin(), members[k].columns.end(), o) == members[k].columns.end())
        throw InputError(a.study + ": member " + std::to_string(k + 1) + ": its summary has no output '" + o +
                         "' (its bodies differ from member 1's: list the outputs to collect in study.outputs)");

  const std::string exe = self_exe();
  const int width = std::min(9, std::max(3, static_cast<int>(std::to_string(sets.size()).size())));
  const int threads = a.threads > 0 ? a.threads
                                    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / std::max(1, a.jobs));
  std::string commands;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    Member& m = members[k];
    char id[48];
    std::snprintf(id, sizeof id, "member-%0*zu", width, k + 1);
    m.sets = sets[k];
    m.folder = (fs::path(out_dir) / id).string();
    m.argv = {exe, "run", study.case_file};
    for (const std::string& s : study.fixed) m.argv.insert(m.argv.end(), {"--set", s});
    for (const std::string& s : m.sets) m.argv.insert(m.argv.end(), {"--set", s});
    m.argv.insert(m.argv.end(), {"-o", m.folder, "-q", "-j", std::to_string(threads)});
    // The line does what the sweep does for the member: its folder, the previous run's
    // outputs removed, the run, its log and its exit code, so that `sh -c LINE` (a job
    // array's task) leaves what --collect reads.
    std::string run_line;
    for (const std::string& arg : m.argv) run_line += (run_line.empty() ? "" : " ") + shell_quote(arg);
    const std::string q = shell_quote(m.folder);
    std::string clear;
    for (const std::string& f : previous_outputs(m)) clear += " " + shell_quote((fs::path(m.folder) / f).string());
    m.command = "mkdir -p " + q + " && rm -f" + clear + " && " + run_line + " > " + q + "/run.log 2>&1; echo $? > " + q +
                "/exit_code";
    commands += m.command + "\n";
  }
  solver::make_folder(out_dir);
  // One command per line: line k runs member k alone (e.g. a cluster job array).
  io::write_file_atomic((fs::path(out_dir) / "commands.txt").string(), commands);
  if (a.dry_run) {
    std::fputs(commands.c_str(), stdout);
    return kExitOk;
  }
  const std::string csv_path = (fs::path(out_dir) / (study.name + ".csv")).string();
  std::error_code ec;
  if (!a.collect) {
    // Nothing of a previous run into this folder is left to be taken for this one's: its
    // table, and each member's exit code, summary, status and effective case. Every member
    // folder is ready before the first member starts.
    fs::remove(csv_path, ec);
    if (ec) throw InputError(csv_path + ": cannot remove the previous table (" + ec.message() + ")");
    for (const Member& m : members) {
      solver::make_folder(m.folder);
      for (const std::string& f : previous_outputs(m)) {
        const fs::path file = fs::path(m.folder) / f;
        fs::remove(file, ec);
        if (ec) throw InputError(file.string() + ": cannot remove the previous run's file (" + ec.message() + ")");
      }
      io::write_file_atomic((fs::path(m.folder) / "command.txt").string(), m.command + "\n");
    }
  }
  if (!a.quiet && !a.collect)
    std::printf("hexdem sweep: %s: %zu members of %s, %d at a time -> %s\n", a.study.c_str(), members.size(),
                study.case_file.c_str(), a.jobs, out_dir.c_str());

  int stopped_by = 0;  // the signal that interrupted the sweep
  std::size_t stopped = 0;
  std::string start_error;
  if (a.collect) {
    // The members ran elsewhere (a job array): read their exit codes, -1 if not run.
    for (Member& m : members) {
      std::ifstream in(fs::path(m.folder) / "exit_code");
      if (!(in >> m.exit_code)) m.exit_code = -1;
    }
  } else {
    std::fflush(stdout);  // not written twice by a member's copy of the buffer
    ForwardStopSignals forward(static_cast<std::size_t>(a.jobs));
    std::map<pid_t, std::size_t> running;
    std::size_t next = 0;
    for (;;) {
      {
        const BlockStopSignals blocked;
        while (next < members.size() && running.size() < static_cast<std::size_t>(a.jobs) && g_sweep_signal == 0 &&
               start_error.empty()) {
          const pid_t pid = spawn(members[next], start_error);
          if (pid < 0) break;
          forward.add(pid);
          running[pid] = next++;
        }
      }
      if (running.empty()) break;
      // Wait for a member without reaping it, so that its pid is not forwarded a signal
      // after it is free for reuse.
      siginfo_t info{};
      if (::waitid(P_ALL, 0, &info, WEXITED | WNOWAIT) < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error(std::string("waiting for member runs: ") + std::strerror(errno));
      }
      int status = 0;
      pid_t pid = 0;
      {
        const BlockStopSignals blocked;
        forward.remove(info.si_pid);
        pid = ::waitpid(info.si_pid, &status, 0);
      }
      const auto it = running.find(pid);
      if (pid <= 0 || it == running.end()) continue;
      Member& m = members[it->second];
      running.erase(it);
      // As a shell reports it: 128 + N for a run ended by signal N.
      m.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
      if (g_sweep_signal != 0) ++stopped;
      const fs::path code_file = fs::path(m.folder) / "exit_code";
      std::ofstream code_out(code_file);
      code_out << m.exit_code << "\n";
      code_out.close();
      if (!code_out)
        std::fprintf(stderr, "hexdem sweep: %s: cannot write the member's exit code %d\n",
                     meshing::escape_text(code_file.string()).c_str(), m.exit_code);
      if (!a.quiet) {
        std::string what;
        for (const std::string& s : m.sets) what += (what.empty() ? "" : " ") + s;
        std::printf("  %s: exit %d  %s\n", fs::path(m.folder).filename().c_str(), m.exit_code, what.c_str());
        std::fflush(stdout);
      }
    }
    stopped_by = g_sweep_signal;
  }
  if (!start_error.empty()) std::fprintf(stderr, "hexdem sweep: %s\n", meshing::escape_text(start_error).c_str());

  // One row per member: its parameter values, exit code, and the chosen final values. A
  // member that exits 3 ran to its end with a run-health warning: it has its values, and the
  // sweep reports it (exit 3 when no member failed). Only a member that ran to its end (exit
  // 0 or 3) with a whole summary has values; one whose summary is missing or incomplete
  // counts as failed. A member that exits 1 or crashed (128 + SIGSEGV, ...) met an internal
  // error (a bug): the sweep passes that on.
  std::size_t failed = 0, warned = 0, internal = 0;
  std::string csv = "member";
  for (const Parameter& p : study.parameters) csv += "," + csv_field(p.key);
  csv += ",exit_code";
  for (const std::string& o : outputs) csv += "," + csv_field(o);
  csv += "\n";
  for (std::size_t k = 0; k < members.size(); ++k) {
    const Member& m = members[k];
    csv += std::to_string(k + 1);
    for (const std::string& s : m.sets) csv += "," + csv_field(s.substr(s.find('=') + 1));
    csv += "," + std::to_string(m.exit_code);
    std::map<std::string, std::string> row;
    if (m.exit_code == kExitOk || m.exit_code == kExitWarning) {
      const fs::path file = fs::path(m.folder) / (m.case_name + ".summary.csv");
      std::string problem;
      row = read_summary(file, m.columns, problem);
      if (row.empty()) {
        std::fprintf(stderr, "hexdem sweep: %s: exit code %d, but its summary %s %s: counted as not run to the end\n",
                     fs::path(m.folder).filename().c_str(), m.exit_code, meshing::escape_text(file.string()).c_str(),
                     problem.c_str());
        ++failed;
      } else {
        warned += m.exit_code == kExitWarning;
      }
    } else {
      ++failed;
      internal += m.exit_code == kExitFailure || crashed(m.exit_code);
    }
    for (const std::string& o : outputs) {
      const auto v = row.find(o);
      csv += "," + (v != row.end() ? v->second : std::string());
    }
    csv += "\n";
  }
  io::write_file_atomic(csv_path, csv);
  if (stopped_by != 0) {
    std::size_t not_run = 0;
    for (const Member& m : members) not_run += m.exit_code == -1;
    std::fprintf(stderr,
                 "hexdem sweep: interrupted by %s: %zu running member(s) stopped, %zu not run (exit code -1); "
                 "table: %s\n",
                 signal_name(stopped_by), stopped, not_run, meshing::escape_text(csv_path).c_str());
    std::fflush(stdout);
    std::fflush(stderr);
    // End by the same signal, as the shell and a job scheduler expect.
    std::signal(stopped_by, SIG_DFL);
    const sigset_t set = stop_signal_set();
    ::sigprocmask(SIG_UNBLOCK, &set, nullptr);
    std::raise(stopped_by);
    return 128 + stopped_by;
  }
  if (!a.quiet) {
    std::printf("  %zu of %zu members ran to the end", members.size() - failed, members.size());
    if (warned > 0) std::printf(", %zu of them with a warning (exit code 3: see their run.log)", warned);
    if (internal > 0) std::printf("; %zu met an internal error or crashed (see their run.log)", internal);
    std::printf("; table: %s\n", csv_path.c_str());
  }
  if (internal > 0) return kExitFailure;
  if (failed > 0) return kExitRunFailed;
  return warned == 0 ? kExitOk : kExitWarning;
}

}  // namespace

Subcommand add_sweep_command(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  CLI::App* cmd = app.add_subcommand(
      "sweep", "Run a parameter study: the members of STUDY.toml as parallel `hexdem run`s, one CSV of final values");
  cmd->add_option("study", args->study, "Study file (.toml, see docs/studies.md)")->required();
  CLI::Option* out = cmd->add_option("-o,--out", args->out, "Output folder (default: <study name>-study)");
  cmd->add_option("--jobs", args->jobs, "Members run at the same time")->check(CLI::Range(1, 1 << 16));
  cmd->add_option("-j,--threads", args->threads, "OpenMP threads per member (default: cores / jobs)")
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--dry-run", args->dry_run,
                "Write and print the members' command lines (one per line, for a job array) without running them");
  cmd->add_flag("--collect", args->collect,
                "Run nothing: build the table from the member folders (members run by a job array; "
                "a member without exit_code counts as not run, -1)");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  return {cmd, [args, out] {
            args->out_given = out->count() > 0;
            return run_sweep(*args);
          }};
}

}  // namespace hexdem::app
