// Streaming VTK XML UnstructuredGrid writer: appended raw binary, zlib blocks, UInt64 headers.
//
// Layout of every appended array, as VTK's vtkXMLWriter writes it and vtkXMLDataParser reads
// it (header_type="UInt64"):
//   [num_blocks, block_size, last_block_size, compressed_size_0 .. compressed_size_{n-1}]
// as little-endian UInt64, followed by the zlib streams of the blocks. `block_size` is the
// uncompressed size of every block but the last; `last_block_size` is the uncompressed size
// of the last block when it is partial, 0 when it is full. An empty array is [0, block_size, 0].
//
// The XML header is written first with blank space reserved for each array's offset; the
// offsets are patched in once the compressed sizes are known (VTK's writer does the same).
// Each array's compression header is likewise reserved and patched after its blocks.

#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/error.hpp"

#include <libdeflate.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace hexdem::io {

static_assert(std::endian::native == std::endian::little,
              "the .vtu writer declares byte_order=\"LittleEndian\" and writes native data");

namespace {

constexpr std::uint8_t kVtkLine = 3;           // VTK_LINE
constexpr std::size_t kOffsetField = 24;       // reserved characters for offset="..."
constexpr std::size_t kBatchBytes = 4u << 20;  // uncompressed bytes filled per batch
constexpr std::size_t kMaxBlockSize = 1u << 30; // zlib counts bytes in 32-bit integers

const char* type_name(ScalarType t) {
  switch (t) {
    case ScalarType::Int8: return "Int8";
    case ScalarType::UInt8: return "UInt8";
    case ScalarType::Int32: return "Int32";
    case ScalarType::Int64: return "Int64";
    case ScalarType::Float32: return "Float32";
    case ScalarType::Float64: return "Float64";
  }
  return "UInt8";
}

std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

/// `<path>.tmp<pid>`; for a name with no room for that suffix (Linux names hold at most 255
/// bytes, and a valid 250-byte output name was refused), `.hexdem<pid>-<n>.tmp` in its folder.
std::string temp_path_for(const std::string& path) {
  static std::atomic<unsigned> count{0};
  const std::string pid = std::to_string(static_cast<long long>(::getpid()));
  const std::size_t slash = path.find_last_of('/');
  const std::size_t name = slash == std::string::npos ? path.size() : path.size() - slash - 1;
  if (name + 4 + pid.size() <= 255) return path + ".tmp" + pid;
  const std::string folder = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  return folder + ".hexdem" + pid + "-" + std::to_string(count++) + ".tmp";
}

std::string errno_text(int err) { return err != 0 ? std::string(": ") + std::strerror(err) : ""; }

/// An open temporary file that becomes `path` on commit() and is removed otherwise.
class AtomicFile {
public:
  explicit AtomicFile(std::string path) : path_(std::move(path)), temp_(temp_path_for(path_)) {
    file_ = std::fopen(temp_.c_str(), "wb");
    if (file_ == nullptr)
      throw InputError("cannot write '" + path_ + "': cannot create '" + temp_ + "'" +
                       errno_text(errno));
    std::setvbuf(file_, nullptr, _IOFBF, 1u << 20);
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (file_ != nullptr) std::fclose(file_);
    if (!committed_) std::remove(temp_.c_str());
  }

  void write(const void* data, std::size_t n) {
    if (n != 0 && std::fwrite(data, 1, n, file_) != n) fail("write failed");
    position_ += n;
  }
  void write(std::string_view s) { write(s.data(), s.size()); }

  /// Bytes written so far (the current end of the file).
  [[nodiscard]] std::uint64_t position() const { return position_; }

  /// Overwrites bytes at an earlier position, then returns to the end.
  void patch(std::uint64_t at, const void* data, std::size_t n) {
    if (fseeko(file_, static_cast<off_t>(at), SEEK_SET) != 0) fail("seek failed");
    if (n != 0 && std::fwrite(data, 1, n, file_) != n) fail("write failed");
    if (fseeko(file_, static_cast<off_t>(position_), SEEK_SET) != 0) fail("seek failed");
  }

  /// Closes the file, checks every error and renames it to the final path.
  void commit() {
    if (std::fflush(file_) != 0 || std::ferror(file_) != 0) fail("write failed");
    std::FILE* f = std::exchange(file_, nullptr);
    if (std::fclose(f) != 0) fail("close failed");
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail("rename failed");
    committed_ = true;
  }

  [[noreturn]] void fail(const std::string& what) const {
    // A full disk or a folder that cannot be written is not a bug: InputError (exit 2).
    throw InputError("cannot write '" + path_ + "': " + what + errno_text(errno));
  }

private:
  std::string path_;
  std::string temp_;
  std::FILE* file_ = nullptr;
  std::uint64_t position_ = 0;
  bool committed_ = false;
};

/// One array to encode: `tuples` tuples of `tuple_bytes` bytes, produced by `fill` or, when
/// `fill` is empty, copied from `payload` (small arrays: field data).
struct Encoded {
  std::string xml;           ///< the element up to (not including) ` offset=`
  std::size_t tuple_bytes = 1;
  std::size_t tuples = 0;
  std::function<void(std::size_t, std::size_t, void*)> fill;
  std::string payload;
  std::size_t offset_at = 0; ///< position of the reserved offset field in the XML header

  void produce(std::size_t first, std::size_t count, void* out) const {
    if (fill)
      fill(first, count, out);
    else
      std::memcpy(out, payload.data() + first * tuple_bytes, count * tuple_bytes);
  }
};

std::string data_array_xml(const std::string& indent, const std::string& name, ScalarType type,
                           int components, const std::string& extra = {}) {
  std::string s = indent + "<DataArray type=\"" + type_name(type) + "\" Name=\"" +
                  xml_escape(name) + "\"";
  if (components > 1) s += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  s += extra;
  s += " format=\"appended\"";
  return s;
}

Encoded from_source(const std::string& indent, const ArraySource& a) {
  Encoded e;
  e.xml = data_array_xml(indent, a.name, a.type, a.components);
  e.tuple_bytes = scalar_size(a.type) * static_cast<std::size_t>(a.components);
  e.tuples = a.tuples;
  e.fill = a.fill;
  return e;
}

/// Per-thread zlib compressors for one write (libdeflate: zlib streams, as VTK's
/// vtkZLibDataCompressor reads them; the warhead's frames were written in 0.8 s against
/// zlib's 1.2 to 1.5 s at level 1, docs/benchmarks.md).
class Compressors {
public:
  Compressors(int count, int level) : compressors_(static_cast<std::size_t>(count), nullptr) {
    for (auto& c : compressors_) {
      c = libdeflate_alloc_compressor(level);
      if (c == nullptr) {
        end();
        throw std::runtime_error("libdeflate: cannot allocate a compressor");
      }
    }
  }
  Compressors(const Compressors&) = delete;
  Compressors& operator=(const Compressors&) = delete;
  ~Compressors() { end(); }

  [[nodiscard]] std::size_t bound(std::size_t n) { return libdeflate_zlib_compress_bound(compressors_[0], n); }

  /// Compresses `n` bytes into `out` (capacity bound(n)); returns the size, or 0 on failure.
  std::size_t compress(int thread, const unsigned char* in, std::size_t n, unsigned char* out,
                       std::size_t capacity) {
    return libdeflate_zlib_compress(compressors_[static_cast<std::size_t>(thread)], in, n, out, capacity);
  }

private:
  void end() {
    for (auto& c : compressors_) {
      if (c != nullptr) libdeflate_free_compressor(c);
      c = nullptr;
    }
  }
  std::vector<libdeflate_compressor*> compressors_;
};

/// Encodes arrays into the appended section: fills batches of blocks serially (the callbacks
/// need not be thread-safe), compresses the blocks of a batch in parallel, writes them in order.
class BlockEncoder {
public:
  /// What the encoder keeps from one write to the next on its thread: the compressors and the
  /// batch buffers. Allocating them (and first touching their pages) for every frame of a
  /// series cost more than compressing the warhead's small frames (docs/benchmarks.md,
  /// "Output"); held: about 2 x 4 MiB plus the compressors, per thread that writes.
  struct Cache {
    int level = -1;
    int threads = 0;
    std::unique_ptr<Compressors> zlib;
    std::vector<std::uint64_t> raw, packed;
    std::vector<std::size_t> sizes;
  };

  BlockEncoder(AtomicFile& file, const WriteOptions& options)
      : file_(file), block_size_(options.block_size), threads_(max_threads()), cache_(thread_cache()) {
    if (!cache_.zlib || cache_.level != options.compression_level || cache_.threads != threads_) {
      cache_.zlib.reset();  // a failed allocation below leaves no half-made compressors behind
      cache_.zlib = std::make_unique<Compressors>(threads_, options.compression_level);
      cache_.level = options.compression_level;
      cache_.threads = threads_;
    }
  }

  /// Writes one array (header + blocks) at the current end of the file.
  void encode(const Encoded& e) {
    // Blocks hold whole tuples, so each fill call maps to contiguous blocks.
    const std::size_t tuples_per_block = std::max<std::size_t>(1, block_size_ / e.tuple_bytes);
    const std::size_t block_bytes = tuples_per_block * e.tuple_bytes;
    const std::size_t total_bytes = e.tuples * e.tuple_bytes;
    const std::size_t num_blocks = (e.tuples + tuples_per_block - 1) / tuples_per_block;
    const std::size_t last_bytes = total_bytes - (num_blocks == 0 ? 0 : (num_blocks - 1) * block_bytes);

    std::vector<std::uint64_t> header(3 + num_blocks, 0);
    header[0] = num_blocks;
    header[1] = block_bytes;
    header[2] = (num_blocks == 0 || last_bytes == block_bytes) ? 0 : last_bytes;
    const std::uint64_t header_at = file_.position();
    file_.write(header.data(), header.size() * sizeof(std::uint64_t));

    const std::size_t batch_blocks = std::min(
        std::max<std::size_t>(num_blocks, 1),
        std::max<std::size_t>({1, kBatchBytes / block_bytes, 4 * static_cast<std::size_t>(threads_)}));
    Compressors& zlib = *cache_.zlib;
    const std::size_t bound = zlib.bound(block_bytes);
    reserve(batch_blocks * block_bytes, batch_blocks * bound);
    auto* raw = reinterpret_cast<unsigned char*>(cache_.raw.data());
    auto* packed = reinterpret_cast<unsigned char*>(cache_.packed.data());
    std::vector<std::size_t>& sizes = cache_.sizes;
    sizes.assign(batch_blocks, 0);

    for (std::size_t b0 = 0; b0 < num_blocks; b0 += batch_blocks) {
      const std::size_t nb = std::min(batch_blocks, num_blocks - b0);
      const std::size_t first = b0 * tuples_per_block;
      const std::size_t count = std::min(nb * tuples_per_block, e.tuples - first);
      e.produce(first, count, raw);
      const std::size_t filled = count * e.tuple_bytes;
      const auto n = static_cast<std::int64_t>(nb);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (nb > 1 && threads_ > 1)
      for (std::int64_t k = 0; k < n; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        const std::size_t len = std::min(block_bytes, filled - kk * block_bytes);
        sizes[kk] = zlib.compress(thread_id(), raw + kk * block_bytes, len, packed + kk * bound, bound);
      }
      for (std::size_t k = 0; k < nb; ++k) {
        if (sizes[k] == 0) throw std::runtime_error("zlib: compression failed");
        header[3 + b0 + k] = sizes[k];
        file_.write(packed + k * bound, sizes[k]);
      }
    }
    if (num_blocks != 0)
      file_.patch(header_at + 3 * sizeof(std::uint64_t), header.data() + 3,
                  num_blocks * sizeof(std::uint64_t));
  }

private:
  static int max_threads() {
#ifdef _OPENMP
    return std::max(1, omp_get_max_threads());
#else
    return 1;
#endif
  }
  static int thread_id() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
  }
  static Cache& thread_cache() {
    static thread_local Cache cache;
    return cache;
  }
  void reserve(std::size_t raw_bytes, std::size_t packed_bytes) {
    // 8-byte words keep every scalar type aligned for the fill callbacks. The buffers only
    // grow: a later, smaller write reuses them.
    const std::size_t raw_words = (raw_bytes + 7) / 8;
    const std::size_t packed_words = (packed_bytes + 7) / 8;
    if (cache_.raw.size() < raw_words) cache_.raw.resize(raw_words);
    if (cache_.packed.size() < packed_words) cache_.packed.resize(packed_words);
  }

  AtomicFile& file_;
  std::size_t block_size_;
  int threads_;
  Cache& cache_;
};

void check_source(const std::string& path, const std::string& group, const ArraySource& a,
                  std::size_t expected_tuples, std::set<std::string>& names) {
  const std::string where = "'" + path + "': " + group + " array '" + a.name + "'";
  if (a.name.empty()) throw std::invalid_argument("'" + path + "': " + group + " array without a name");
  if (!names.insert(a.name).second) throw std::invalid_argument(where + " appears twice");
  if (a.components < 1) throw std::invalid_argument(where + " has no components");
  if (a.tuples != expected_tuples)
    throw std::invalid_argument(where + " has " + std::to_string(a.tuples) + " tuples, expected " +
                                std::to_string(expected_tuples));
  if (a.tuples != 0 && !a.fill) throw std::invalid_argument(where + " has no fill function");
}

void check_grid(const std::string& path, const LineGrid& g) {
  const std::string where = "'" + path + "': ";
  if (g.points) {
    if (g.points->tuples != g.num_points || g.points->components != 3 ||
        g.points->type != ScalarType::Float64 || !g.points->fill)
      throw std::invalid_argument(where + "points source must be Float64 x 3 with num_points tuples");
  } else if (g.num_points != 0 && (g.x == nullptr || g.y == nullptr)) {
    throw std::invalid_argument(where + "points without x or y coordinates");
  }
  if (g.num_points > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) + 1)
    throw std::invalid_argument(where + "too many points for Int32 point ids");
  auto check_lines = [&](std::size_t n, const std::int32_t* a, const std::int32_t* b,
                         const char* what) {
    if (n == 0) return;
    if (a == nullptr || b == nullptr) throw std::invalid_argument(where + what + " without point ids");
    const auto np = static_cast<std::int64_t>(g.num_points);
    for (std::size_t k = 0; k < n; ++k) {
      if (a[k] < 0 || a[k] >= np || b[k] < 0 || b[k] >= np)
        throw std::invalid_argument(where + what + " " + std::to_string(k) +
                                    " refers to a point that does not exist");
    }
  };
  check_lines(g.num_lines, g.line_i, g.line_j, "line");
  check_lines(g.num_extra_lines, g.extra_i, g.extra_j, "extra line");

  std::set<std::string> names;
  for (const auto& a : g.point_data) check_source(path, "point", a, g.num_points, names);
  names.clear();
  for (const auto& a : g.cell_data)
    check_source(path, "cell", a, g.num_lines + g.num_extra_lines, names);
  names.clear();
  for (const auto& f : g.field_data) {
    if (f.name.empty()) throw std::invalid_argument(where + "field data entry without a name");
    if (!names.insert(f.name).second)
      throw std::invalid_argument(where + "field data entry '" + f.name + "' appears twice");
    auto has_nul = [](const std::string& s) { return s.find('\0') != std::string::npos; };
    if (has_nul(f.text) || std::any_of(f.strings.begin(), f.strings.end(), has_nul))
      throw std::invalid_argument(where + "field data string '" + f.name + "' contains a NUL");
  }
}

Encoded field_entry(const FieldValue& f) {
  const std::string indent = "      ";
  Encoded e;
  if (!f.strings.empty() || !f.text.empty()) {
    const std::vector<std::string> one{f.text};
    const auto& strings = f.strings.empty() ? one : f.strings;
    // VTK stores a String array as its values, each followed by a NUL, compressed as bytes.
    for (const auto& s : strings) {
      e.payload += s;
      e.payload += '\0';
    }
    e.xml = indent + "<Array type=\"String\" Name=\"" + xml_escape(f.name) +
            "\" NumberOfTuples=\"" + std::to_string(strings.size()) + "\" format=\"appended\"";
    e.tuple_bytes = 1;
    e.tuples = e.payload.size();
  } else {
    const int components = std::max<int>(1, static_cast<int>(f.numbers.size()));
    e.payload.assign(reinterpret_cast<const char*>(f.numbers.data()),
                     f.numbers.size() * sizeof(double));
    e.xml = data_array_xml(indent, f.name, ScalarType::Float64, components,
                           " NumberOfTuples=\"" + std::string(f.numbers.empty() ? "0" : "1") + "\"");
    e.tuple_bytes = sizeof(double) * static_cast<std::size_t>(components);
    e.tuples = f.numbers.empty() ? 0 : 1;
  }
  return e;
}

}  // namespace

std::size_t scalar_size(ScalarType t) {
  switch (t) {
    case ScalarType::Int8:
    case ScalarType::UInt8: return 1;
    case ScalarType::Int32:
    case ScalarType::Float32: return 4;
    case ScalarType::Int64:
    case ScalarType::Float64: return 8;
  }
  return 1;
}

namespace {
template <typename T>
ArraySource contiguous_view(std::string name, ScalarType type, const T* data, std::size_t n) {
  ArraySource a;
  a.name = std::move(name);
  a.type = type;
  a.components = 1;
  a.tuples = n;
  a.fill = [data](std::size_t first, std::size_t count, void* out) {
    std::memcpy(out, data + first, count * sizeof(T));
  };
  return a;
}
}  // namespace

ArraySource array_view(std::string name, const double* data, std::size_t n) {
  return contiguous_view(std::move(name), ScalarType::Float64, data, n);
}
ArraySource array_view(std::string name, const std::int32_t* data, std::size_t n) {
  return contiguous_view(std::move(name), ScalarType::Int32, data, n);
}
ArraySource array_view(std::string name, const std::uint8_t* data, std::size_t n) {
  return contiguous_view(std::move(name), ScalarType::UInt8, data, n);
}

ArraySource vector_view(std::string name, const double* x, const double* y, const double* z,
                        std::size_t n) {
  ArraySource a;
  a.name = std::move(name);
  a.type = ScalarType::Float64;
  a.components = 3;
  a.tuples = n;
  a.fill = [x, y, z](std::size_t first, std::size_t count, void* out) {
    auto* o = static_cast<double*>(out);
    const double* xs = x + first;
    const double* ys = y + first;
    if (z != nullptr) {
      const double* zs = z + first;
      for (std::size_t k = 0; k < count; ++k) {
        o[3 * k] = xs[k];
        o[3 * k + 1] = ys[k];
        o[3 * k + 2] = zs[k];
      }
    } else {
      for (std::size_t k = 0; k < count; ++k) {
        o[3 * k] = xs[k];
        o[3 * k + 1] = ys[k];
        o[3 * k + 2] = 0.0;
      }
    }
  };
  return a;
}

void write_vtu(const std::string& path, const LineGrid& grid, const WriteOptions& options) {
  check_grid(path, grid);
  if (options.compression_level < 0 || options.compression_level > 9)
    throw std::invalid_argument("'" + path + "': zlib compression level " +
                                std::to_string(options.compression_level) + " is not in 0-9");
  if (options.block_size == 0 || options.block_size > kMaxBlockSize)
    throw std::invalid_argument("'" + path + "': block size " + std::to_string(options.block_size) +
                                " is not in 1-" + std::to_string(kMaxBlockSize));

  const std::size_t num_cells = grid.num_lines + grid.num_extra_lines;
  std::vector<Encoded> arrays;

  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n"
      "  <UnstructuredGrid>\n";
  auto add = [&](Encoded e) {
    xml += e.xml;
    xml += " offset=";
    e.offset_at = xml.size();
    xml.append(kOffsetField, ' ');
    xml += "/>\n";
    arrays.push_back(std::move(e));
  };

  if (!grid.field_data.empty()) {
    xml += "    <FieldData>\n";
    for (const auto& f : grid.field_data) add(field_entry(f));
    xml += "    </FieldData>\n";
  }
  xml += "    <Piece NumberOfPoints=\"" + std::to_string(grid.num_points) + "\" NumberOfCells=\"" +
         std::to_string(num_cells) + "\">\n";
  const std::string indent = "        ";
  xml += "      <PointData>\n";
  for (const auto& a : grid.point_data) add(from_source(indent, a));
  xml += "      </PointData>\n      <CellData>\n";
  for (const auto& a : grid.cell_data) add(from_source(indent, a));
  xml += "      </CellData>\n      <Points>\n";
  if (grid.points) {
    ArraySource p = *grid.points;
    p.name = "Points";
    add(from_source(indent, p));
  } else {
    add(from_source(indent, vector_view("Points", grid.x, grid.y, grid.z, grid.num_points)));
  }
  xml += "      </Points>\n      <Cells>\n";

  // Connectivity: the point ids are Int32, so Int32 always fits.
  {
    Encoded e;
    e.xml = data_array_xml(indent, "connectivity", ScalarType::Int32, 1);
    e.tuple_bytes = 2 * sizeof(std::int32_t);
    e.tuples = num_cells;
    const LineGrid* g = &grid;
    e.fill = [g](std::size_t first, std::size_t count, void* out) {
      auto* o = static_cast<std::int32_t*>(out);
      std::size_t k = 0;
      for (std::size_t c = first; c < std::min(first + count, g->num_lines); ++c, ++k) {
        o[2 * k] = g->line_i[c];
        o[2 * k + 1] = g->line_j[c];
      }
      for (std::size_t c = std::max(first, g->num_lines); c < first + count; ++c, ++k) {
        o[2 * k] = g->extra_i[c - g->num_lines];
        o[2 * k + 1] = g->extra_j[c - g->num_lines];
      }
    };
    add(std::move(e));
  }
  // Offsets: end of each cell in the connectivity, 2, 4, ...
  {
    const bool small = 2 * num_cells <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
    Encoded e;
    e.xml = data_array_xml(indent, "offsets", small ? ScalarType::Int32 : ScalarType::Int64, 1);
    e.tuples = num_cells;
    if (small) {
      e.tuple_bytes = sizeof(std::int32_t);
      e.fill = [](std::size_t first, std::size_t count, void* out) {
        auto* o = static_cast<std::int32_t*>(out);
        for (std::size_t k = 0; k < count; ++k) o[k] = static_cast<std::int32_t>(2 * (first + k + 1));
      };
    } else {
      e.tuple_bytes = sizeof(std::int64_t);
      e.fill = [](std::size_t first, std::size_t count, void* out) {
        auto* o = static_cast<std::int64_t*>(out);
        for (std::size_t k = 0; k < count; ++k) o[k] = static_cast<std::int64_t>(2 * (first + k + 1));
      };
    }
    add(std::move(e));
  }
  {
    Encoded e;
    e.xml = data_array_xml(indent, "types", ScalarType::UInt8, 1);
    e.tuple_bytes = 1;
    e.tuples = num_cells;
    e.fill = [](std::size_t, std::size_t count, void* out) { std::memset(out, kVtkLine, count); };
    add(std::move(e));
  }
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

  AtomicFile file(path);
  file.write(xml);
  const std::uint64_t data_start = file.position();
  {
    BlockEncoder encoder(file, options);
    for (auto& e : arrays) {
      const std::uint64_t offset = file.position() - data_start;
      std::string field(1, '"');
      field += std::to_string(offset);
      field += '"';
      std::memcpy(xml.data() + e.offset_at, field.data(), field.size());
      encoder.encode(e);
    }
  }
  file.write("\n  </AppendedData>\n</VTKFile>\n");
  file.patch(0, xml.data(), xml.size());
  file.commit();
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicFile file(path);
  file.write(content);
  file.commit();
}

void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  char time[64];
  for (const auto& e : entries) {
    if (!std::isfinite(e.time))
      throw std::invalid_argument("'" + path + "': time of '" + e.file + "' is not finite");
    std::snprintf(time, sizeof time, "%.17g", e.time);
    xml += "    <DataSet timestep=\"";
    xml += time;
    xml += "\" group=\"\" part=\"0\" file=\"" + xml_escape(e.file) + "\"/>\n";
  }
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

}  // namespace hexdem::io
