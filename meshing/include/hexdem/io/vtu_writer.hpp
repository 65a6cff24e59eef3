#pragma once
/// \file vtu_writer.hpp
/// Streaming writer for VTK XML UnstructuredGrid (.vtu) files made of points and line cells,
/// in appended raw binary with zlib-compressed blocks (header type UInt64), as ParaView 5.11
/// and VTK 9 read them. Arrays are produced block by block from callbacks, so structure-of-
/// arrays data are written without building interleaved copies; blocks are compressed in
/// parallel with OpenMP. Files are written to a temporary name and renamed on success, so a
/// crash never leaves a truncated file under the final name.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hexdem::io {

enum class ScalarType : std::uint8_t { Int8, UInt8, Int32, Int64, Float32, Float64 };

/// Size in bytes of one scalar.
std::size_t scalar_size(ScalarType t);

/// One data array. `fill(first, count, out)` writes tuples [first, first+count) as
/// count*components scalars of `type` to `out` (which is suitably aligned).
/// write_vtu calls `fill` from the calling thread only, for consecutive ranges in increasing
/// order (about 4 MB per call at the default block size), so it need not be thread-safe.
struct ArraySource {
  std::string name;
  ScalarType type = ScalarType::Float64;
  int components = 1;
  std::size_t tuples = 0;
  std::function<void(std::size_t first, std::size_t count, void* out)> fill;
};

/// Helpers to make sources from contiguous arrays (not copied: they must outlive write()).
ArraySource array_view(std::string name, const double* data, std::size_t n);
ArraySource array_view(std::string name, const std::int32_t* data, std::size_t n);
ArraySource array_view(std::string name, const std::uint8_t* data, std::size_t n);
/// Three-component array (x, y, z) from separate component arrays; z may be null (zeros).
ArraySource vector_view(std::string name, const double* x, const double* y, const double* z,
                        std::size_t n);

/// A field-data entry (one tuple): numeric values or a string.
struct FieldValue {
  std::string name;
  std::vector<double> numbers;  ///< written as Float64 when `text` is empty
  std::string text;             ///< written as a String array when not empty
  /// Several strings: written as a String array with one tuple per string when not empty
  /// (takes precedence over `text` and `numbers`). Strings must not contain NUL characters.
  std::vector<std::string> strings;
};

/// Points (x, y, z) and line cells (two point ids each), plus point, cell and field data.
struct LineGrid {
  std::size_t num_points = 0;
  const double* x = nullptr;  ///< point coordinates; z may be null (zeros)
  const double* y = nullptr;
  const double* z = nullptr;
  /// Alternative to x, y, z: the coordinates as a 3-component Float64 source with
  /// num_points tuples (e.g. reference position plus displacement, computed per block).
  std::optional<ArraySource> points;
  std::size_t num_lines = 0;
  const std::int32_t* line_i = nullptr;  ///< first point of each line
  const std::int32_t* line_j = nullptr;  ///< second point of each line
  /// Optional second set of lines appended after the first (e.g. contacts); may be empty.
  std::size_t num_extra_lines = 0;
  const std::int32_t* extra_i = nullptr;
  const std::int32_t* extra_j = nullptr;
  std::vector<ArraySource> point_data;
  std::vector<ArraySource> cell_data;   ///< tuples must equal num_lines + num_extra_lines
  std::vector<FieldValue> field_data;
};

struct WriteOptions {
  int compression_level = 1;       ///< zlib level 0-9 (1: fast; ParaView reads any)
  std::size_t block_size = 1 << 15; ///< uncompressed bytes per compressed block (1 B - 1 GiB;
                                    ///< rounded down to whole tuples, at least one tuple)
};

/// Writes `grid` to `path` atomically (temporary file + rename). Throws std::runtime_error
/// naming the path on an I/O failure; no file is left under `path` then. Throws
/// std::invalid_argument for an inconsistent grid (a line id outside the points, an array
/// with the wrong number of tuples, a duplicate or empty array name, bad options).
void write_vtu(const std::string& path, const LineGrid& grid, const WriteOptions& options = {});

/// One entry of a ParaView data collection (.pvd).
struct PvdEntry {
  double time = 0.0;   ///< simulated time [s]
  std::string file;    ///< path relative to the .pvd's folder
};

/// Writes a .pvd collection atomically.
void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries);

/// Writes `content` to `path` via a temporary file in the same folder and rename().
void write_file_atomic(const std::string& path, const std::string& content);

}  // namespace hexdem::io
