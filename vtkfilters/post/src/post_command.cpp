// The `hexdem post` command line (CLI11 lives in this file only: its headers are slow).

#include "hexdem/post/post_command.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "hexdem/post/post.hpp"

namespace hexdem::post {
namespace {

/// Values the parser writes into, shared by the three subcommands (only one is parsed).
struct Parsed {
  PostOptions options;
  double time = 0.0;
  double max_break_time = 0.0;
  std::map<CLI::App*, Analysis> analyses;
  std::map<CLI::App*, CLI::Option*> time_options;
  std::map<CLI::App*, CLI::Option*> break_time_options;
};

CLI::App* add_analysis(CLI::App& post, Parsed& p, Analysis analysis, const std::string& help) {
  CLI::App* sub = post.add_subcommand(analysis_name(analysis), help);
  PostOptions& o = p.options;
  sub->add_option("input", o.input, "Result series (.pvd) or frame (.vtu)")->required();
  CLI::Option* time = sub->add_option("-t,--time", p.time,
                                      "Use the series frame nearest this time [s] "
                                      "(default: the last frame)");
  CLI::Option* all = sub->add_flag("-a,--all", o.all, "Process every frame of the series");
  time->excludes(all);
  sub->add_option("-o,--output", o.output,
                  "Output path; the extension is replaced (.vtu/.vtp/.pvd and .csv are written; "
                  "default: <input name>_" +
                      std::string(analysis_name(analysis)) + ")");
  sub->add_flag("--csv-only", o.csv_only, "Write the CSV table only");
  sub->add_flag("-q,--quiet", o.quiet, "Print nothing on success");
  p.analyses[sub] = analysis;
  p.time_options[sub] = time;
  return sub;
}

}  // namespace

PostCommand add_post_command(CLI::App& app) {
  auto parsed = std::make_shared<Parsed>();
  Parsed& p = *parsed;
  PostOptions& o = p.options;
  CLI::App* post = app.add_subcommand(
      "post", "Post-process result frames: maximum shear stress, crack maps, fragments");
  post->require_subcommand(1);

  CLI::App* maxshear = add_analysis(
      *post, p, Analysis::MaxShear,
      "Maximum shear stress of every disk (max_shear, max_shear_ratio = tau_max/p_max)");
  const std::map<std::string, int> sources = {{"auto", 0}, {"array", 1}, {"bonds", 2}};
  maxshear
      ->add_option("--stress", o.stress_source,
                   "Stress source: auto (the 'stress' array, else bond forces), array, bonds")
      ->transform(CLI::CheckedTransformer(sources, CLI::ignore_case));
  maxshear->add_flag("--3d", o.three_d, "Also the 3D maximum shear (s_1 - s_3)/2 with s_zz");
  maxshear->add_option("--p-max", o.p_max, "Peak pressure p_max [Pa] (overrides the frames')");
  maxshear->add_option("--thickness", o.thickness,
                       "Thickness [m] for stress recovery (overrides the frames')");

  CLI::App* cracks = add_analysis(*post, p, Analysis::Cracks,
                                  "Crack map: one segment per broken bond, merged into polylines");
  cracks->add_flag("!--no-merge", o.merge, "One line per broken bond (no polylines)");
  cracks->add_option("--merge-tolerance", o.merge_tolerance,
                     "End points closer than this fraction of the disk radius are merged (0.1)");
  p.break_time_options[cracks] = cracks->add_option("--max-break-time", p.max_break_time,
                                                    "Only bonds broken at or before this time [s]");

  CLI::App* fragments = add_analysis(*post, p, Analysis::Fragments,
                                     "Fragments: disks connected by intact bonds, and their table");
  fragments->add_option("--min-disks", o.min_disks,
                        "Count only fragments of at least this many disks (1)");

  auto run = [parsed]() -> int {
    Parsed& p = *parsed;
    for (const auto& [sub, analysis] : p.analyses) {
      if (!sub->parsed()) continue;
      PostOptions o = p.options;
      o.analysis = analysis;
      if (p.time_options.at(sub)->count() > 0) o.time = p.time;
      const auto bt = p.break_time_options.find(sub);
      if (bt != p.break_time_options.end() && bt->second->count() > 0) {
        o.max_break_time = p.max_break_time;
      }
      run_post(o, std::cout, std::cerr);
      return 0;
    }
    return 0;
  };
  return PostCommand{post, run};
}

}  // namespace hexdem::post
