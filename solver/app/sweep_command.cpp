// `hexdem sweep STUDY.toml`: a parameter study (docs/studies.md). Each member is the case
// with its own --set values, run as a child `hexdem run` in its own folder; the final values
// of the members' `<case>.summary.csv` go into one CSV, one row per member.
#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <sys/wait.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/meshing/toml_values.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/run_summary.hpp"
#include "subcommands.hpp"

namespace hexdem::app {
namespace {

namespace fs = std::filesystem;
using meshing::describe;

struct SweepArgs {
  std::string study;
  std::string out;
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
  int exit_code = -1;
};

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
      fs::path file(text());
      if (file.is_relative()) file = fs::path(path).parent_path() / file;
      s.case_file = fs::absolute(file).lexically_normal().string();
      if (!std::ifstream(s.case_file))
        throw InputError(where + ": cannot open case file '" + s.case_file + "' (got " + describe(node) + ")");
    } else if (k == "name") {
      s.name = text();
      if (s.name.empty() || s.name.find_first_of("/\\ ") != std::string::npos)
        throw InputError(where + ": must be a non-empty name without '/' or spaces (got " + describe(node) + ")");
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

pid_t spawn(const Member& m) {
  const std::string log = (fs::path(m.folder) / "run.log").string();
  std::vector<char*> argv;
  for (const std::string& a : m.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("cannot start a member run (") + std::strerror(errno) + ")");
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    ::execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

/// The row of `file` (a summary CSV) as column -> text.
std::map<std::string, std::string> read_summary(const fs::path& file) {
  std::ifstream in(file);
  std::string header, row;
  std::map<std::string, std::string> out;
  if (!std::getline(in, header) || !std::getline(in, row)) return out;
  std::stringstream h(header), r(row);
  std::string name, value;
  while (std::getline(h, name, ',') && std::getline(r, value, ',')) out[name] = value;
  return out;
}

int run_sweep(const SweepArgs& a) {
  const Study study = read_study(a.study);
  const std::vector<std::vector<std::string>> sets = member_sets(study);
  // Absolute, so that the written command lines run from any folder.
  const std::string out_dir = fs::absolute(a.out.empty() ? study.name + "-study" : a.out).lexically_normal().string();

  // Every member's case is read (with its overrides) before anything runs: a bad value
  // stops the study with the case reader's message.
  std::vector<std::string> bodies;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    std::vector<std::string> all = study.fixed;
    all.insert(all.end(), sets[k].begin(), sets[k].end());
    try {
      const solver::Case c = solver::read_case(study.case_file, all);
      if (k == 0)
        for (const auto& b : c.outline.bodies) bodies.push_back(b.name);
    } catch (const InputError& e) {
      throw InputError(a.study + ": member " + std::to_string(k + 1) + ": " + e.what());
    }
  }
  const std::vector<std::string> columns = solver::run_summary_columns(bodies);
  std::vector<std::string> outputs = study.outputs.empty() ? columns : study.outputs;
  for (const std::string& o : outputs)
    if (std::find(columns.begin(), columns.end(), o) == columns.end()) {
      std::string list;
      for (const std::string& c : columns) list += (list.empty() ? "" : ", ") + c;
      throw InputError(a.study + ": study.outputs: unknown output '" + o + "' (outputs: " + list + ")");
    }

  const std::string exe = self_exe();
  std::vector<Member> members(sets.size());
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
    // The line does what the sweep does for the member: its folder, the run, its log and its
    // exit code, so that `sh -c LINE` (a job array's task) leaves what --collect reads.
    std::string run_line;
    for (const std::string& arg : m.argv) run_line += (run_line.empty() ? "" : " ") + shell_quote(arg);
    const std::string q = shell_quote(m.folder);
    m.command = "mkdir -p " + q + " && " + run_line + " > " + q + "/run.log 2>&1; echo $? > " + q + "/exit_code";
    commands += m.command + "\n";
  }
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error(out_dir + ": cannot create folder (" + ec.message() + ")");
  // One command per line: line k runs member k alone (e.g. a cluster job array).
  io::write_file_atomic((fs::path(out_dir) / "commands.txt").string(), commands);
  if (a.dry_run) {
    std::fputs(commands.c_str(), stdout);
    return kExitOk;
  }
  if (!a.quiet && !a.collect)
    std::printf("hexdem sweep: %s: %zu members of %s, %d at a time -> %s\n", a.study.c_str(), members.size(),
                study.case_file.c_str(), a.jobs, out_dir.c_str());

  std::map<pid_t, std::size_t> running;
  // A member that exits 3 ran to its end with a run-health warning: it has its values, and
  // the sweep reports it (exit 3 when no member failed).
  // A member that exits 1 met an internal error (a bug): the sweep passes that on.
  std::size_t next = 0, failed = 0, warned = 0, internal = 0;
  const auto tally = [&](int code) {
    failed += code != 0 && code != kExitWarning;
    warned += code == kExitWarning;
    internal += code == kExitFailure;
  };
  if (a.collect) {
    // The members ran elsewhere (a job array): read their exit codes, -1 if not run.
    for (Member& m : members) {
      std::ifstream in(fs::path(m.folder) / "exit_code");
      if (!(in >> m.exit_code)) m.exit_code = -1;
      tally(m.exit_code);
    }
    next = members.size();
  }
  while (next < members.size() || !running.empty()) {
    while (next < members.size() && running.size() < static_cast<std::size_t>(a.jobs)) {
      Member& m = members[next];
      fs::create_directories(m.folder, ec);
      std::ofstream(fs::path(m.folder) / "command.txt") << m.command << "\n";
      fs::remove(fs::path(m.folder) / "exit_code", ec);
      running[spawn(m)] = next++;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waiting for member runs: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    Member& m = members[it->second];
    running.erase(it);
    m.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    std::ofstream(fs::path(m.folder) / "exit_code") << m.exit_code << "\n";
    tally(m.exit_code);
    if (!a.quiet) {
      std::string what;
      for (const std::string& s : m.sets) what += (what.empty() ? "" : " ") + s;
      std::printf("  %s: exit %d  %s\n", fs::path(m.folder).filename().c_str(), m.exit_code, what.c_str());
      std::fflush(stdout);
    }
  }

  // One row per member: its parameter values, exit code, and the chosen final values.
  const solver::Case base = solver::read_case(study.case_file, study.fixed);
  std::string csv = "member";
  for (const Parameter& p : study.parameters) csv += "," + p.key;
  csv += ",exit_code";
  for (const std::string& o : outputs) csv += "," + o;
  csv += "\n";
  for (std::size_t k = 0; k < members.size(); ++k) {
    const Member& m = members[k];
    csv += std::to_string(k + 1);
    for (const std::string& s : m.sets) {
      std::string v = s.substr(s.find('=') + 1);
      if (v.find_first_of(",\"") != std::string::npos) {
        std::string q = "\"";
        for (char ch : v) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        v = q + "\"";
      }
      csv += "," + v;
    }
    csv += "," + std::to_string(m.exit_code);
    const auto row = read_summary(fs::path(m.folder) / (base.name + ".summary.csv"));
    for (const std::string& o : outputs) {
      const auto v = row.find(o);
      csv += "," + (v != row.end() ? v->second : std::string());
    }
    csv += "\n";
  }
  const std::string csv_path = (fs::path(out_dir) / (study.name + ".csv")).string();
  io::write_file_atomic(csv_path, csv);
  if (!a.quiet) {
    std::printf("  %zu of %zu members ran to the end", members.size() - failed, members.size());
    if (warned > 0) std::printf(", %zu of them with a warning (exit code 3: see their run.log)", warned);
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
  cmd->add_option("-o,--out", args->out, "Output folder (default: <study name>-study)");
  cmd->add_option("--jobs", args->jobs, "Members run at the same time")->check(CLI::Range(1, 1 << 16));
  cmd->add_option("-j,--threads", args->threads, "OpenMP threads per member (default: cores / jobs)")
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--dry-run", args->dry_run,
                "Write and print the members' command lines (one per line, for a job array) without running them");
  cmd->add_flag("--collect", args->collect,
                "Run nothing: build the table from the member folders (members run by a job array; "
                "a member without exit_code counts as not run, -1)");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  return {cmd, [args] { return run_sweep(*args); }};
}

}  // namespace hexdem::app
