// The run's own health and its output's integrity, end to end: a disk too fast for its
// contacts stops the run; SIGINT and SIGTERM stop it with a whole series; a long series is
// listed in full; a new run removes frames only; a restart refuses changed boundary sets.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli_runner.hpp"

extern char** environ;

namespace hexdem::testing {
namespace {

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

/// A 2 x 1 mm block (r = 0.5 mm) over a 1 mm plate held at both ends, the block moving down
/// at `speed` [m/s].
std::string projectile_case(double speed) {
  return R"([case]
name = "shot"
geometry = "plane-stress"
[lattice]
radius = 0.5e-3
[[body]]
name = "plate"
[[body.shape]]
type = "rectangle"
min = [-0.01, -0.001]
max = [0.01, 0.0]
boundary = { left = "ends", right = "ends" }
[[body]]
name = "proj"
[[body.shape]]
type = "rectangle"
min = [-0.001, 0.002]
max = [0.001, 0.003]
[[material]]
id = 1
density = 2400.0
E = 30e9
nu = 0.2
[[boundary]]
set = "ends"
type = "fixed"
[[initial_velocity]]
body = "proj"
velocity = [0.0, )" + std::to_string(-speed) + R"(]
[time]
end = 10e-6
[output]
interval = 5e-6
body_history = ["proj", "plate"]
)";
}

/// The frames a .pvd lists, by file name.
std::set<std::string> listed_frames(const fs::path& pvd) {
  const std::string text = slurp(pvd);
  std::set<std::string> out;
  const std::regex re("file=\"[^\"]*/([^\"/]+\\.vtu)\"");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    out.insert((*it)[1]);
  return out;
}

std::set<std::string> vtu_files(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".vtu") out.insert(e.path().filename().string());
  return out;
}

/// A plate under a ramped pressure: `end` [s], a frame every `interval` [s], checkpoints.
std::string plate_case(const std::string& end, const std::string& interval, const std::string& sets) {
  return R"([case]
name = "p"
geometry = "plane-stress"
[lattice]
radius = 0.5e-3
[[body]]
name = "plate"
[[body.shape]]
type = "rectangle"
min = [0, -0.01]
max = [0.01, 0]
boundary = )" + sets + R"(
[[material]]
id = 1
density = 2400.0
E = 30e9
nu = 0.2
[[boundary]]
set = "base"
type = "fixed"
[[load]]
type = "pressure"
set = "top"
p0 = 1e6
function = { type = "ramp-hold", t1 = 2e-6, t2 = 1.0 }
[time]
end = )" + end + R"(
[output]
interval = )" + interval + R"(
checkpoint_interval = 2e-6
)";
}

const std::string kSets = R"({ bottom = "base", top = "top" })";

TEST(RunHealth, ADiskFasterThanHalfARadiusPerStepStopsTheRunWhereContactsAct) {
  // Was: at 5,000 m/s the block crossed the plate unseen (its speed kept, the plate at rest),
  // exit 0.
  const fs::path d = test_dir("cli_run_health", true);
  const fs::path c = write(d, "shot.toml", projectile_case(5000.0));
  const Result r = run_hexdem(d, "run " + c.string() + " -q -j 1 -o " + (d / "fast").string());
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("contacts cannot stop it"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("times its radius 0.0005 m"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(d / "fast" / "shot.status").rfind("failed: numerical blow-up", 0), 0u);
  // At 500 m/s (0.19 r per step) the plate stops the block: the run completes.
  const fs::path slow = write(d, "slow.toml", projectile_case(500.0));
  const Result ok = run_hexdem(d, "run " + slow.string() + " -q -j 1 -o " + (d / "slow").string());
  EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST(RunHealth, SigintAndSigtermStopTheRunWithAWholeSeries) {
  const fs::path d = test_dir("cli_run_health", true);
  const fs::path c = write(d, "p.toml", plate_case("1.0", "1e-6", kSets));
  for (const int sig : {SIGINT, SIGTERM}) {
    const fs::path out = d / ("out" + std::to_string(sig));
    std::string bin = HEXDEM_BINARY;
    const std::string o = out.string(), cs = c.string();
    std::vector<char*> argv = {bin.data(), const_cast<char*>("run"), const_cast<char*>(cs.c_str()),
                               const_cast<char*>("-q"), const_cast<char*>("-j"), const_cast<char*>("1"),
                               const_cast<char*>("-o"), const_cast<char*>(o.c_str()), nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, (d / "err.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, bin.c_str(), &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    // Wait for a few frames and the first checkpoint, then signal.
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!(fs::exists(out / "p.chk") && fs::exists(out / "p") && vtu_files(out / "p").size() >= 5) &&
           std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_TRUE(fs::exists(out / "p.chk")) << "no checkpoint within 120 s";
    kill(pid, sig);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "the run was killed by the signal instead of stopping";
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    const std::string err = slurp(d / "err.txt");
    EXPECT_EQ(count_lines(err), 1) << err;
    EXPECT_NE(err.find(sig == SIGINT ? "interrupted by SIGINT" : "interrupted by SIGTERM"), std::string::npos) << err;
    const std::string st = slurp(out / "p.status");
    EXPECT_EQ(st.rfind("interrupted at t = ", 0), 0u) << st;
    EXPECT_NE(st.find(sig == SIGINT ? "(SIGINT)" : "(SIGTERM)"), std::string::npos) << st;
    // The .pvd lists exactly the frames written, and a restart goes on from the checkpoint.
    EXPECT_EQ(listed_frames(out / "p.pvd"), vtu_files(out / "p"));
    EXPECT_GE(vtu_files(out / "p").size(), 5u);
  }
  const Result r = run_hexdem(d, "run " + write(d, "short.toml", plate_case("4e-6", "1e-6", kSets)).string() +
                                     " -q -j 1 -o " + (d / "short").string());
  ASSERT_EQ(r.code, 0) << r.err;
}

TEST(RunHealth, ALongSeriesIsListedInFullAndTheFolderKeepsFilesThatAreNotFrames) {
  const fs::path d = test_dir("cli_run_health", true);
  // 300 frames: the .pvd is rewritten lazily after the first 16, and in full at the end.
  const fs::path c = write(d, "p.toml", plate_case("70e-6", "1e-7", kSets));
  fs::create_directories(d / "out" / "p");
  for (const char* keep : {"p_notes.vtu", "p_1.vtu", "p_.vtu", "p_00000001x.vtu", "other_000000001.vtu"})
    std::ofstream(d / "out" / "p" / keep) << "mine";
  std::ofstream(d / "out" / "p" / "p_000000007.vtu") << "an old frame";
  const Result r = run_hexdem(d, "run " + c.string() + " -q -j 1 -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::set<std::string> frames = vtu_files(d / "out" / "p");
  for (const char* keep : {"p_notes.vtu", "p_1.vtu", "p_.vtu", "p_00000001x.vtu", "other_000000001.vtu"}) {
    EXPECT_EQ(frames.count(keep), 1u) << keep << " is not a frame of the run: it stays";
    frames.erase(keep);
  }
  EXPECT_GE(frames.size(), 300u);
  EXPECT_EQ(listed_frames(d / "out" / "p.pvd"), frames);
  EXPECT_NE(slurp(d / "out" / "p" / "p_000000007.vtu"), "an old frame") << "the old frame was removed (or rewritten)";
}

TEST(RunHealth, ARestartRefusesAnOutlineWhoseBoundarySetsChanged) {
  // Was: the restart went on with the checkpoint's conditions and wrote frames with the new
  // sets' arrays and stresses (the outline file is not part of the case; its lattice is).
  const fs::path d = test_dir("cli_run_health", true);
  const auto outline = [&](const std::string& sets) {
    write(d, "outline.toml", R"([lattice]
radius = 0.5e-3
[[body]]
name = "plate"
material = 1
[[body.shape]]
type = "rectangle"
min = [0, -0.01]
max = [0.01, 0]
boundary = )" + sets + "\n");
  };
  outline(kSets);
  const fs::path c = write(d, "p.toml", R"([case]
name = "p"
geometry = "plane-stress"
[mesh]
outline = "outline.toml"
[[material]]
id = 1
density = 2400.0
E = 30e9
nu = 0.2
[[boundary]]
set = "base"
type = "fixed"
[[load]]
type = "pressure"
set = "top"
p0 = 1e6
function = { type = "ramp-hold", t1 = 2e-6, t2 = 1.0 }
[time]
end = 6e-6
[output]
interval = 1e-6
checkpoint_interval = 2e-6
)");
  Result r = run_hexdem(d, "run " + c.string() + " -q -j 1 -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  // The same lattice, the set names swapped (both sets still exist).
  outline(R"({ bottom = "top", top = "base" })");
  r = run_hexdem(d, "run " + c.string() + " -q -j 1 --restart " + (d / "out" / "p.chk").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("checkpoint of another lattice or other boundary sets"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(d / "out" / "p.status"), "completed\n");
  // The unchanged outline restarts.
  outline(kSets);
  r = run_hexdem(d, "run " + c.string() + " -q -j 1 --restart " + (d / "out" / "p.chk").string());
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(RunHealth, NoFrameFolderWithoutFramesAndAnUnwritableReportIsNotASuccess) {
  const fs::path d = test_dir("cli_run_health", true);
  std::string text = plate_case("4e-6", "1e-6", kSets);
  text.replace(text.find("[output]\n"), 9, "[output]\nframes = false\n");
  const fs::path c = write(d, "p.toml", text);
  Result r = run_hexdem(d, "run " + c.string() + " -q -j 1 -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(d / "out" / "p")) << "an empty frame folder was made";
  EXPECT_TRUE(fs::exists(d / "out" / "p.energy.csv"));
  // stdout on a full device: the report is lost, so the exit code is not 0 (was 0).
  const std::string cmd = std::string(HEXDEM_BINARY) + " check " + c.string() + " > /dev/full 2> " +
                          (d / "err.txt").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string err = slurp(d / "err.txt");
  EXPECT_EQ(count_lines(err), 1) << err;
  EXPECT_NE(err.find("cannot write to standard output"), std::string::npos) << err;
}

TEST(OutputNames, ANameWithNoRoomForTheTemporarySuffixIsWritten) {
  // Was: "File name too long" for a valid 250-byte name (the temporary file's name is longer).
  const fs::path d = test_dir("cli_run_health", true);
  write(d, "outline.toml", R"([lattice]
radius = 0.5e-3
[[body]]
name = "plate"
[[body.shape]]
type = "rectangle"
min = [0, -0.005]
max = [0.005, 0]
)");
  const std::string name = std::string(246, 'm') + ".vtu";  // 250 bytes
  const Result r = run_hexdem(d, "mesh " + (d / "outline.toml").string() + " -q -j 1 -o " + (d / name).string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / name));
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find("tmp"), std::string::npos) << "left behind: " << e.path();
}

}  // namespace
}  // namespace hexdem::testing
