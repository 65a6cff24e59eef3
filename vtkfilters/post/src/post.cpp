// hexdem post: reads frames, runs one of the hexdem VTK filters on them, writes the results.

#include "hexdem/post/post.hpp"

#include <vtkAbstractArray.h>
#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkHexDEMCrackMap.h>
#include <vtkHexDEMFragmentCounter.h>
#include <vtkHexDEMMaxShearStress.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringOutputWindow.h>
#include <vtkTable.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <sys/stat.h>

#include "hexdem/error.hpp"
#include "hexdem/meshing/text.hpp"
#include "vtu_check.hpp"

namespace hexdem::post {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Sends VTK's own messages (the pipeline's "returned failure" reports, XML parser errors)
/// to a string instead of stderr while hexdem post runs, so that the user sees our one-line
/// errors only. VTK prints them both through the output window and through its logger.
class VtkMessageSink {
 public:
  VtkMessageSink()
      : previous_(vtkOutputWindow::GetInstance()),
        previous_verbosity_(vtkLogger::GetCurrentVerbosityCutoff()) {
    vtkOutputWindow::SetInstance(sink_);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~VtkMessageSink() {
    vtkLogger::SetStderrVerbosity(previous_verbosity_);
    vtkOutputWindow::SetInstance(previous_);
  }
  VtkMessageSink(const VtkMessageSink&) = delete;
  VtkMessageSink& operator=(const VtkMessageSink&) = delete;

  /// Everything VTK printed since the previous call.
  std::string take() {
    const std::string all = sink_->GetOutput();
    std::string fresh = all.substr(std::min(seen_, all.size()));
    seen_ = all.size();
    return fresh;
  }

 private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkLogger::Verbosity previous_verbosity_;
  vtkNew<vtkStringOutputWindow> sink_;
  std::size_t seen_ = 0;
};

/// The message of a VTK error or warning report, on one line, without the file/line
/// header and the "vtkClass (0x...): " prefix.
std::string one_line(const std::string& report) {
  std::string text = report;
  const std::size_t prefix = text.find("): ");
  if (prefix != std::string::npos) text = text.substr(prefix + 3);
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  return text;
}

/// Records the errors and warnings an object reports.
class Reports {
 public:
  explicit Reports(vtkObject* object) {
    observer_->SetClientData(this);
    observer_->SetCallback([](vtkObject*, unsigned long event, void* client, void* call) {
      auto* self = static_cast<Reports*>(client);
      const std::string text = one_line(call ? static_cast<const char*>(call) : "");
      (event == vtkCommand::ErrorEvent ? self->errors : self->warnings).push_back(text);
    });
    object->AddObserver(vtkCommand::ErrorEvent, observer_);
    object->AddObserver(vtkCommand::WarningEvent, observer_);
  }
  std::vector<std::string> errors;
  std::vector<std::string> warnings;

 private:
  vtkNew<vtkCallbackCommand> observer_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string format_number(double v) {
  if (std::isnan(v)) return "";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

/// A number for messages: like format_number, but NaN is "nan".
std::string number_text(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

double field_number(vtkFieldData* fd, const char* name) {
  if (!fd) return kNaN;
  vtkDataArray* a = vtkDataArray::SafeDownCast(fd->GetAbstractArray(name));
  return (a && a->GetNumberOfTuples() > 0) ? a->GetComponent(0, 0) : kNaN;
}

/// Writes `content` to `path` through a temporary file and a rename; InputError naming the
/// path and the reason (a full disk, a folder of that name) on failure, leaving nothing.
void write_text_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot write the file (" + std::strerror(errno) + ")");
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size() &&
                       std::fflush(f) == 0;
  const int write_errno = errno;
  const bool closed = std::fclose(f) == 0;
  std::error_code ec;
  if (!written || !closed) {
    fs::remove(tmp, ec);
    throw InputError(path + ": cannot write the file (" +
                     std::strerror(!written ? write_errno : errno) + ")");
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InputError(path + ": cannot write the file (" + ec.message() + ")");
  }
}

/// Writes a filter output as a VTK XML file (appended raw binary, zlib), atomically: the
/// temporary file becomes `path` only when the writer reports no error (VTK's Write() returns
/// success on a full disk; its error code does not).
void write_vtk(const std::string& path, vtkDataObject* data, VtkMessageSink& sink) {
  const std::string tmp = path + ".tmp";
  int ok = 0;
  unsigned long error = vtkErrorCode::NoError;
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data)) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetInputData(grid);
    writer->SetFileName(tmp.c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
    writer->SetHeaderTypeToUInt64();
    errno = 0;
    ok = writer->Write();
    error = writer->GetErrorCode();
  } else if (auto* poly = vtkPolyData::SafeDownCast(data)) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(poly);
    writer->SetFileName(tmp.c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
    writer->SetHeaderTypeToUInt64();
    errno = 0;
    ok = writer->Write();
    error = writer->GetErrorCode();
  }
  const int write_errno = errno;
  sink.take();  // the writer's own report must not be blamed on the next input frame
  std::error_code ec;
  if (ok != 1 || error != vtkErrorCode::NoError) {
    fs::remove(tmp, ec);
    std::string reason = error == vtkErrorCode::OutOfDiskSpaceError
                             ? std::string("no space left on the device")
                             : (write_errno != 0 ? std::string(std::strerror(write_errno))
                                                 : "VTK writer error code " + std::to_string(error));
    throw InputError(path + ": cannot write the file (" + reason + ")");
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InputError(path + ": cannot write the file (" + ec.message() + ")");
  }
}

/// Throws InputError "PATH: no such file" or "PATH: not a regular file" (a folder, a device
/// such as /dev/zero, a FIFO) unless `path` is a regular file (or a link to one).
void check_regular_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(path + ": no such file");
  if (!fs::is_regular_file(status)) {
    throw InputError(path + ": not a regular file (" +
                     (fs::is_directory(status) ? "a folder" : "a device, FIFO or socket") + ")");
  }
}

/// Reads one .vtu frame; throws InputError naming the file when it cannot.
vtkSmartPointer<vtkUnstructuredGrid> read_frame(const std::string& path, VtkMessageSink& sink) {
  check_regular_file(path);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  Reports reports(reader);
  if (!reader->CanReadFile(path.c_str())) {
    sink.take();
    throw InputError(path + ": not a VTK XML unstructured grid (.vtu) file");
  }
  sink.take();
  check_vtu_file(path);
  reader->SetFileName(path.c_str());
  reader->Update();
  const std::string vtk_text = sink.take();
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  const bool no_points = std::all_of(
      reports.errors.begin(), reports.errors.end(),
      [](const std::string& e) { return e.find("No Points element") != std::string::npos; });
  if (!reports.errors.empty() && no_points && grid->GetNumberOfPoints() == 0) {
    throw InputError(path + ": the frame has no disks (empty grid)");
  }
  if (!reports.errors.empty() || vtk_text.find("ERR") != std::string::npos) {
    const std::string why = !reports.errors.empty() ? reports.errors.front() : "corrupt file";
    throw InputError(path + ": cannot read the frame (" + meshing::one_line(why) + ")");
  }
  check_grid(path, grid);
  check_frame_values(path, grid);
  return grid;
}

/// The filter of an analysis, configured from the options.
vtkSmartPointer<vtkAlgorithm> make_filter(const PostOptions& o) {
  switch (o.analysis) {
    case Analysis::MaxShear: {
      auto f = vtkSmartPointer<vtkHexDEMMaxShearStress>::New();
      f->SetStressSource(o.stress_source);
      f->SetComputeThreeDimensional(o.three_d);
      f->SetPMax(o.p_max);
      f->SetThickness(o.thickness);
      return f;
    }
    case Analysis::Cracks: {
      auto f = vtkSmartPointer<vtkHexDEMCrackMap>::New();
      f->SetMergeSegments(o.merge);
      f->SetMergeTolerance(o.merge_tolerance);
      f->SetUseMaxBreakTime(o.max_break_time.has_value());
      f->SetMaxBreakTime(o.max_break_time.value_or(0.0));
      return f;
    }
    case Analysis::Fragments: {
      auto f = vtkSmartPointer<vtkHexDEMFragmentCounter>::New();
      f->SetMinimumDisks(o.min_disks);
      return f;
    }
  }
  return nullptr;
}

/// Column names of the per-frame summary.
std::vector<std::string> summary_header(const PostOptions& o) {
  switch (o.analysis) {
    case Analysis::MaxShear: {
      std::vector<std::string> h = {"time",     "step",     "max_shear_max",
                                    "x_at_max", "y_at_max", "max_shear_ratio_max"};
      if (o.three_d) h.insert(h.end(), {"max_shear_3d_max", "max_shear_3d_ratio_max"});
      return h;
    }
    case Analysis::Cracks:
      return {"time",
              "step",
              "crack_count",
              "crack_length",
              "crack_count_tension",
              "crack_length_tension",
              "crack_count_shear",
              "crack_length_shear",
              "crack_count_compression",
              "crack_length_compression",
              "crack_line_count"};
    case Analysis::Fragments:
      return {"time",
              "step",
              "fragment_count",
              "fragment_count_total",
              "largest_disks",
              "largest_mass",
              "largest_equivalent_diameter"};
  }
  return {};
}

/// Largest value of a point array and the index where it is reached (-1 without the array).
std::pair<double, vtkIdType> array_max(vtkDataSet* data, const char* name) {
  vtkDataArray* a = data->GetPointData()->GetArray(name);
  if (!a || a->GetNumberOfTuples() == 0) return {kNaN, -1};
  vtkIdType best = 0;
  double value = a->GetComponent(0, 0);
  for (vtkIdType i = 1; i < a->GetNumberOfTuples(); ++i) {
    const double v = a->GetComponent(i, 0);
    if (v > value) {
      value = v;
      best = i;
    }
  }
  return {value, best};
}

/// The summary row of one filtered frame, and a one-line description for the console.
std::vector<double> summary_row(const PostOptions& o, double time, vtkAlgorithm* filter,
                                std::string& description) {
  vtkDataObject* out = filter->GetOutputDataObject(0);
  vtkFieldData* fd = out->GetFieldData();
  const double step = field_number(fd, "step");
  std::ostringstream text;
  std::vector<double> row = {time, step};
  switch (o.analysis) {
    case Analysis::MaxShear: {
      auto* grid = vtkDataSet::SafeDownCast(out);
      const auto [tau, at] = array_max(grid, "max_shear");
      double p[3] = {kNaN, kNaN, kNaN};
      if (at >= 0) grid->GetPoint(at, p);
      const double ratio = array_max(grid, "max_shear_ratio").first;
      row.insert(row.end(), {tau, p[0], p[1], ratio});
      if (o.three_d) {
        row.push_back(array_max(grid, "max_shear_3d").first);
        row.push_back(array_max(grid, "max_shear_3d_ratio").first);
      }
      text << "max tau_max " << format_number(tau) << " Pa at (" << format_number(p[0]) << ", "
           << format_number(p[1]) << ")";
      if (!std::isnan(ratio)) text << ", max tau_max/p_max " << format_number(ratio);
      break;
    }
    case Analysis::Cracks: {
      for (const char* name :
           {"crack_count", "crack_length", "crack_count_tension", "crack_length_tension",
            "crack_count_shear", "crack_length_shear", "crack_count_compression",
            "crack_length_compression", "crack_line_count"}) {
        row.push_back(field_number(fd, name));
      }
      text << format_number(row[2]) << " broken bonds (tension " << format_number(row[4])
           << ", shear " << format_number(row[6]) << ", compression " << format_number(row[8])
           << "), crack length " << format_number(row[3]) << " m";
      break;
    }
    case Analysis::Fragments: {
      vtkTable* table = vtkTable::SafeDownCast(filter->GetOutputDataObject(1));
      const double count = field_number(fd, "fragment_count");
      double disks = kNaN, mass = kNaN, diameter = kNaN;
      if (table && table->GetNumberOfRows() > 0) {
        disks = table->GetValueByName(0, "disks").ToDouble();
        mass = table->GetValueByName(0, "mass").ToDouble();
        diameter = table->GetValueByName(0, "equivalent_diameter").ToDouble();
      }
      row.insert(row.end(),
                 {count, field_number(fd, "fragment_count_total"), disks, mass, diameter});
      text << format_number(count) << (count == 1 ? " fragment" : " fragments")
           << ", the largest with " << format_number(disks) << " disks";
      break;
    }
  }
  description = text.str();
  return row;
}

std::string csv_line(const std::vector<double>& values) {
  std::string line;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k) line += ',';
    line += format_number(values[k]);
  }
  return line + "\n";
}

std::string csv_header_line(const std::vector<std::string>& names) {
  std::string line;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k) line += ',';
    line += names[k];
  }
  return line + "\n";
}

/// The fragment table as CSV.
std::string table_csv(vtkTable* table) {
  std::string text;
  std::vector<std::string> names;
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
    names.push_back(table->GetColumnName(c));
  text += csv_header_line(names);
  for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r) {
    std::string line;
    for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c) {
      if (c) line += ',';
      if (table->GetColumn(c)->IsA("vtkStringArray")) {
        // A text column (body_name): quoted (RFC 4180) when it holds a comma or a quote.
        const std::string v = table->GetValue(r, c).ToString();
        if (v.find_first_of(",\"\n") == std::string::npos) {
          line += v;
        } else {
          line += '"';
          for (char ch : v) line += ch == '"' ? std::string("\"\"") : std::string(1, ch);
          line += '"';
        }
      } else {
        line += format_number(table->GetValue(r, c).ToDouble());
      }
    }
    text += line + "\n";
  }
  return text;
}

/// Output path without its extension; checks that its folder exists.
std::string output_base(const PostOptions& o) {
  std::string out = o.output;
  if (out.empty()) out = fs::path(o.input).stem().string() + "_" + analysis_name(o.analysis);
  const std::string ext = lower_extension(out);
  if (ext == ".vtu" || ext == ".vtp" || ext == ".pvd" || ext == ".csv") {
    out = (fs::path(out).parent_path() / fs::path(out).stem()).string();
  }
  const fs::path folder = fs::path(out).parent_path();
  if (!folder.empty() && !fs::is_directory(folder)) {
    throw InputError("-o: folder '" + folder.string() + "' does not exist");
  }
  return out;
}

}  // namespace

const char* analysis_name(Analysis analysis) {
  switch (analysis) {
    case Analysis::MaxShear:
      return "maxshear";
    case Analysis::Cracks:
      return "cracks";
    case Analysis::Fragments:
      return "fragments";
  }
  return "";
}

std::vector<SeriesFrame> read_series(const std::string& path) {
  check_regular_file(path);
  const std::string ext = lower_extension(path);
  if (ext == ".vtu") return {SeriesFrame{kNaN, path}};
  if (ext != ".pvd") {
    throw InputError(path + ": unknown input format '" + ext + "' (expected .pvd or .vtu)");
  }
  {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) throw InputError(path + ": cannot read the file (" + ec.message() + ")");
    if (size > kMaxPvdBytes)
      throw InputError(path + ": file larger than " + std::to_string(kMaxPvdBytes) + " bytes (not a .pvd?)");
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    check_xml_nesting(path, text.str());
  }
  VtkMessageSink sink;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(path.c_str());
  if (parser->Parse() != 1) throw InputError(path + ": not a readable .pvd (XML) file");
  vtkXMLDataElement* root = parser->GetRootElement();
  vtkXMLDataElement* collection = root ? root->FindNestedElementWithName("Collection") : nullptr;
  if (!root || std::string(root->GetName()) != "VTKFile" || !collection) {
    throw InputError(path + ": not a .pvd collection (no <VTKFile><Collection>)");
  }
  const fs::path folder = fs::path(path).parent_path();
  std::vector<SeriesFrame> frames;
  for (int k = 0; k < collection->GetNumberOfNestedElements(); ++k) {
    vtkXMLDataElement* e = collection->GetNestedElement(k);
    if (std::string(e->GetName()) != "DataSet") continue;
    const char* file = e->GetAttribute("file");
    if (!file || !*file) throw InputError(path + ": a <DataSet> has no file attribute");
    int part = 0;
    if (e->GetScalarAttribute("part", part) && part != 0) {
      throw InputError(path + ": multi-part series are not supported (part=\"" +
                       std::to_string(part) + "\")");
    }
    double time = 0.0;
    if (const char* stamp = e->GetAttribute("timestep")) {
      std::string_view v(stamp);
      while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front()))) v.remove_prefix(1);
      while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back()))) v.remove_suffix(1);
      if (!v.empty() && v.front() == '+') v.remove_prefix(1);
      const auto r = std::from_chars(v.data(), v.data() + v.size(), time);
      if (v.empty() || r.ec != std::errc() || r.ptr != v.data() + v.size() || !std::isfinite(time))
        throw InputError(path + ": <DataSet file=\"" + meshing::escape_text(file) +
                         "\"> has timestep=\"" + meshing::escape_text(stamp) +
                         "\", which is not a finite number");
    }
    const fs::path p(file);
    frames.push_back({time, (p.is_absolute() ? p : folder / p).string()});
  }
  if (frames.empty()) throw InputError(path + ": the series lists no frames");
  std::stable_sort(frames.begin(), frames.end(),
                   [](const SeriesFrame& a, const SeriesFrame& b) { return a.time < b.time; });
  return frames;
}

std::size_t nearest_frame(const std::vector<SeriesFrame>& frames, double time) {
  // Beyond the series' ends the nearest frame is the end's (the differences below round to
  // the same value for a time such as 1e300, and the first frame won every tie).
  if (!frames.empty() && time >= frames.back().time) return frames.size() - 1;
  std::size_t best = 0;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    if (std::abs(frames[k].time - time) < std::abs(frames[best].time - time)) best = k;
  }
  return best;
}

namespace {
/// The frames of run_post: filters and writes them, then the .pvd and the CSV; appends every
/// file written to `written` as soon as it exists.
void run_frames(const PostOptions& o, const std::vector<SeriesFrame>& selected,
                const std::string& base, const fs::path& frame_folder,
                const std::function<std::string(std::size_t)>& frame_name,
                const std::string& extension, std::ostream& out, std::ostream& err,
                std::vector<std::string>& written);
}  // namespace

std::vector<std::string> run_post(const PostOptions& o, std::ostream& out, std::ostream& err) {
  if (o.all && o.time) throw InputError("--time and --all: give one of them");
  if (o.time && std::isnan(*o.time)) throw InputError("--time: must be a number of seconds (got nan)");
  if (!(std::isfinite(o.p_max) && o.p_max >= 0)) {
    throw InputError("--p-max: must be a finite number >= 0 (got " + number_text(o.p_max) + ")");
  }
  if (o.p_max > 0 && !std::isfinite(1.0 / o.p_max)) {
    throw InputError("--p-max: " + number_text(o.p_max) +
                     " Pa is too small (1/p_max overflows); give 0 or a larger value");
  }
  if (!(std::isfinite(o.thickness) && o.thickness >= 0)) {
    throw InputError("--thickness: must be a finite number >= 0 (got " +
                     number_text(o.thickness) + ")");
  }
  if (o.max_break_time && !std::isfinite(*o.max_break_time)) {
    throw InputError("--max-break-time: must be a finite number of seconds (got " +
                     number_text(*o.max_break_time) + ")");
  }
  if (!(o.merge_tolerance >= 0 && o.merge_tolerance <= 0.5)) {
    throw InputError("--merge-tolerance: must be in [0, 0.5] (got " +
                     number_text(o.merge_tolerance) + ")");
  }
  if (o.min_disks < 1) {
    throw InputError("--min-disks: must be >= 1 (got " + std::to_string(o.min_disks) + ")");
  }
  std::vector<SeriesFrame> frames = read_series(o.input);
  const bool series = lower_extension(o.input) == ".pvd";
  if (o.time && !series) {
    throw InputError("--time: needs a .pvd series (got the single frame " + o.input + ")");
  }
  std::vector<SeriesFrame> selected;
  if (o.all) {
    selected = frames;
  } else if (o.time) {
    selected = {frames[nearest_frame(frames, *o.time)]};
  } else {
    selected = {frames.back()};
  }
  const std::string base = output_base(o);
  const bool many = o.all;
  const std::string extension = o.analysis == Analysis::Cracks ? ".vtp" : ".vtu";
  const fs::path frame_folder = base + "_frames";
  const auto frame_name = [&](std::size_t k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06zu", k);
    return std::string(name) + extension;
  };
  // No output may replace one of the command's inputs (the .pvd or .vtu given, or a frame
  // of the series): compared by device and inode, so that links and "./" are seen through.
  {
    std::map<std::pair<dev_t, ino_t>, std::string> inputs;
    const auto identity = [](const std::string& path, std::pair<dev_t, ino_t>& id) {
      struct stat st {};
      if (::stat(path.c_str(), &st) != 0) return false;
      id = {st.st_dev, st.st_ino};
      return true;
    };
    std::pair<dev_t, ino_t> id;
    if (identity(o.input, id)) inputs.emplace(id, o.input);
    for (const SeriesFrame& f : frames)
      if (identity(f.path, id)) inputs.emplace(id, f.path);
    std::vector<std::string> outputs;
    if (!o.csv_only) {
      if (many) {
        for (std::size_t k = 0; k < selected.size(); ++k)
          outputs.push_back((frame_folder / frame_name(k)).string());
        outputs.push_back(base + ".pvd");
      } else {
        outputs.push_back(base + extension);
      }
    }
    outputs.push_back(base + ".csv");
    for (const std::string& output : outputs) {
      const auto hit = identity(output, id) ? inputs.find(id) : inputs.end();
      if (hit != inputs.end()) {
        throw InputError("-o: the output " + output + " would overwrite the input " +
                         hit->second + "; choose another -o");
      }
    }
  }

  // On failure nothing is left behind: the files written so far are removed, and the frame
  // folder when this command created it.
  std::vector<std::string> written;
  bool created_folder = false;
  try {
    if (many && !o.csv_only) {
      std::error_code ec;
      created_folder = fs::create_directories(frame_folder, ec);
      if (ec)
        throw InputError(frame_folder.string() + ": cannot create the folder (" + ec.message() +
                         ")");
    }
    run_frames(o, selected, base, frame_folder, frame_name, extension, out, err, written);
  } catch (...) {
    std::error_code ignored;
    for (const std::string& path : written) fs::remove(path, ignored);
    if (created_folder) fs::remove(frame_folder, ignored);  // only when empty
    throw;
  }
  return written;
}

namespace {
void run_frames(const PostOptions& o, const std::vector<SeriesFrame>& selected,
                const std::string& base, const fs::path& frame_folder,
                const std::function<std::string(std::size_t)>& frame_name,
                const std::string& extension, std::ostream& out, std::ostream& err,
                std::vector<std::string>& written) {
  const bool many = o.all;
  VtkMessageSink sink;
  vtkSmartPointer<vtkAlgorithm> filter = make_filter(o);
  Reports reports(filter);
  std::set<std::string> warned;
  std::string csv = csv_header_line(summary_header(o));
  std::string summary;
  std::string pvd;
  for (std::size_t k = 0; k < selected.size(); ++k) {
    const SeriesFrame& frame = selected[k];
    vtkSmartPointer<vtkUnstructuredGrid> grid = read_frame(frame.path, sink);
    double time = frame.time;
    if (std::isnan(time)) {
      time = field_number(grid->GetFieldData(), "time");
      if (std::isnan(time)) time = 0.0;
    }
    reports.errors.clear();
    reports.warnings.clear();
    filter->SetInputDataObject(grid);
    filter->Update();
    sink.take();
    if (!reports.errors.empty()) throw InputError(frame.path + ": " + reports.errors.front());
    for (const std::string& w : reports.warnings) {
      if (!o.quiet && warned.insert(w).second)
        err << "hexdem: warning: " << frame.path << ": " << w << "\n";
    }
    std::string description;
    csv += csv_line(summary_row(o, time, filter, description));

    std::string target;
    if (!o.csv_only) {
      if (many) {
        target = (frame_folder / frame_name(k)).string();
        const std::string relative = (fs::path(frame_folder.filename()) / frame_name(k)).string();
        char stamp[40];
        std::snprintf(stamp, sizeof stamp, "%.17g", time);
        pvd += std::string("    <DataSet timestep=\"") + stamp +
               "\" group=\"\" part=\"0\" file=\"" + relative + "\"/>\n";
      } else {
        target = base + extension;
      }
      write_vtk(target, filter->GetOutputDataObject(0), sink);
      written.push_back(target);
    }
    if (!o.quiet) {
      // Printed once everything is written: no success line before a failure.
      std::ostringstream line;
      line << "hexdem post " << analysis_name(o.analysis) << ": " << frame.path
           << " (t = " << format_number(time) << " s): " << description;
      if (!target.empty()) line << " -> " << target;
      summary += line.str() + "\n";
    }
    if (!many && o.analysis == Analysis::Fragments) {
      csv = table_csv(vtkTable::SafeDownCast(filter->GetOutputDataObject(1)));
    }
  }
  if (many && !o.csv_only) {
    const std::string pvd_path = base + ".pvd";
    write_text_atomic(pvd_path,
                      "<?xml version=\"1.0\"?>\n"
                      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                      "  <Collection>\n" +
                          pvd + "  </Collection>\n</VTKFile>\n");
    written.push_back(pvd_path);
  }
  const std::string csv_path = base + ".csv";
  write_text_atomic(csv_path, csv);
  written.push_back(csv_path);
  if (!o.quiet) out << summary << "  table -> " << csv_path << "\n";
}
}  // namespace

}  // namespace hexdem::post
