#pragma once
/// \file post.hpp
/// `hexdem post`: runs the hexdem VTK filters (maximum shear stress, crack map, fragment
/// counter) on a result frame (.vtu) or on frames of a series (.pvd) and writes the filtered
/// frames (.vtu/.vtp, and a .pvd for a series) and a CSV table. See docs/filters.md.
///
/// Bad input (a missing or unreadable file, a frame without the arrays an analysis needs,
/// an option that does not fit the input) throws hexdem::InputError with a one-line
/// message naming the file or option and the value.

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace hexdem::post {

/// The three analyses.
enum class Analysis { MaxShear, Cracks, Fragments };

/// Command name of an analysis: "maxshear", "cracks", "fragments".
const char* analysis_name(Analysis analysis);

/// What to run, on what, and where to write it.
struct PostOptions {
  Analysis analysis = Analysis::Fragments;
  std::string input;           ///< a .pvd series or a .vtu frame
  std::optional<double> time;  ///< the series frame nearest this time [s] (.pvd only)
  bool all = false;            ///< every frame of the series
  /// Output path; its extension (.vtu, .vtp, .pvd, .csv) is optional and replaced. Empty:
  /// `<input stem>_<analysis>` in the current folder.
  std::string output;
  bool csv_only = false;  ///< write the CSV only, no VTK files
  bool quiet = false;     ///< print nothing on success

  // maxshear
  int stress_source = 0;   ///< 0 automatic, 1 point array `stress`, 2 bond forces
  bool three_d = false;    ///< also max_shear_3d
  double p_max = 0.0;      ///< [Pa]; > 0 overrides the frames' p_max
  double thickness = 0.0;  ///< [m]; > 0 overrides the frames' thickness
  // cracks
  bool merge = true;                     ///< merge segments into polylines
  double merge_tolerance = 0.1;          ///< fraction of the smallest mean radius
  std::optional<double> max_break_time;  ///< [s]
  // fragments
  int min_disks = 1;
};

/// One frame of a series.
struct SeriesFrame {
  double time = 0.0;  ///< [s] (from the .pvd; for a lone .vtu, its `time` field data or 0)
  std::string path;   ///< the frame's .vtu
};

/// The frames of a .pvd, sorted by time, or the one frame of a .vtu. Throws InputError for a
/// missing or unreadable file, an unknown extension, or an empty or multi-part series.
std::vector<SeriesFrame> read_series(const std::string& path);

/// Index of the frame whose time is nearest `time` (the earlier one on a tie).
std::size_t nearest_frame(const std::vector<SeriesFrame>& frames, double time);

/// Runs an analysis. Prints a summary to `out` unless options.quiet (and warnings to `err`).
/// Returns the files written. Throws InputError on bad input.
std::vector<std::string> run_post(const PostOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hexdem::post
