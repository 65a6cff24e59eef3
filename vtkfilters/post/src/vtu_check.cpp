// Checks of VTK XML files against their own headers, before VTK believes them (vtu_check.hpp).
// Format: "VTK File Formats", XML section (kitware.com/vtk-file-formats, VTK 9): the
// appended-data and inline-binary headers are [nbytes] uncompressed, or
// [nblocks, block size, last block size (0: full), compressed size of each block]
// compressed, each of header_type (UInt32 or UInt64) in the file's byte order.

#include "vtu_check.hpp"

#include <vtkAbstractArray.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/text.hpp"

namespace hexdem::post {
namespace {

using meshing::escape_text;

/// Largest ratio of uncompressed to compressed size of one block that is believed: zlib's
/// deflate reaches at most about 1032:1 (zlib technical details, "maximum compression
/// factor"), LZ4 about 255:1; LZMA can do more on constant data, which hexdem never writes.
constexpr std::uint64_t kMaxCompressionRatio = 1100;

struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
  int parent = -1;
  std::size_t text_begin = 0, text_end = 0;  ///< character data up to the first child or end
};

struct Document {
  std::vector<Element> elements;
  std::optional<std::size_t> appended_begin;  ///< file offset after the '_' of AppendedData
  std::string appended_encoding;
};

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

/// Parses the element structure of `text` (up to the appended data) without recursion.
Document parse_structure(const std::string& path, std::string_view text, bool stop_at_appended) {
  Document doc;
  std::vector<int> open;
  std::size_t k = 0;
  const auto find = [&](std::string_view what, std::size_t from) {
    const std::size_t at = text.find(what, from);
    if (at == std::string_view::npos) fail(path, "damaged XML (unterminated markup)");
    return at;
  };
  while (true) {
    const std::size_t lt = text.find('<', k);
    if (lt == std::string_view::npos) break;
    if (!open.empty() && doc.elements[open.back()].text_end == 0)
      doc.elements[open.back()].text_end = lt;
    if (text.substr(lt, 4) == "<!--") {
      k = find("-->", lt + 4) + 3;
      continue;
    }
    if (text.substr(lt, 2) == "<?" ) {
      k = find("?>", lt + 2) + 2;
      continue;
    }
    if (text.substr(lt, 9) == "<![CDATA[") {
      k = find("]]>", lt + 9) + 3;
      continue;
    }
    if (text.substr(lt, 2) == "<!") {
      k = find(">", lt + 2) + 1;
      continue;
    }
    if (text.substr(lt, 2) == "</") {
      const std::size_t gt = find(">", lt + 2);
      std::string_view name = text.substr(lt + 2, gt - lt - 2);
      while (!name.empty() && (name.back() == ' ' || name.back() == '\t' || name.back() == '\r' || name.back() == '\n'))
        name.remove_suffix(1);
      if (open.empty() || doc.elements[open.back()].name != name)
        fail(path, "damaged XML (closing tag </" + escape_text(std::string(name.substr(0, 40))) +
                       "> does not match)");
      open.pop_back();
      k = gt + 1;
      continue;
    }
    // An opening tag: name, attributes, '>' or '/>'.
    std::size_t p = lt + 1;
    const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    const std::size_t name_begin = p;
    while (p < text.size() && !is_space(text[p]) && text[p] != '>' && text[p] != '/') ++p;
    Element e;
    e.name = std::string(text.substr(name_begin, p - name_begin));
    if (e.name.empty()) fail(path, "damaged XML (a tag without a name)");
    bool self_closing = false;
    while (true) {
      while (p < text.size() && is_space(text[p])) ++p;
      if (p >= text.size()) fail(path, "damaged XML (unterminated tag <" + escape_text(e.name.substr(0, 40)) + ">)");
      if (text[p] == '>') break;
      if (text[p] == '/') {
        if (p + 1 < text.size() && text[p + 1] == '>') {
          self_closing = true;
          ++p;
          break;
        }
        fail(path, "damaged XML (stray '/' in <" + escape_text(e.name.substr(0, 40)) + ">)");
      }
      const std::size_t key_begin = p;
      while (p < text.size() && text[p] != '=' && !is_space(text[p]) && text[p] != '>') ++p;
      const std::string key(text.substr(key_begin, p - key_begin));
      while (p < text.size() && is_space(text[p])) ++p;
      if (p >= text.size() || text[p] != '=')
        fail(path, "damaged XML (attribute '" + escape_text(key.substr(0, 40)) + "' without a value)");
      ++p;
      while (p < text.size() && is_space(text[p])) ++p;
      if (p >= text.size() || (text[p] != '"' && text[p] != '\''))
        fail(path, "damaged XML (attribute '" + escape_text(key.substr(0, 40)) + "' not quoted)");
      const char quote = text[p++];
      const std::size_t value_end = find(std::string_view(&quote, 1), p);
      e.attributes[key] = std::string(text.substr(p, value_end - p));
      p = value_end + 1;
    }
    k = p + 1;
    e.parent = open.empty() ? -1 : open.back();
    e.text_begin = k;
    doc.elements.push_back(std::move(e));
    const int index = static_cast<int>(doc.elements.size() - 1);
    if (doc.elements[index].name == "AppendedData" && stop_at_appended) {
      doc.appended_encoding = doc.elements[index].attributes["encoding"];
      const std::size_t underscore = text.find('_', k);
      if (underscore == std::string_view::npos) fail(path, "AppendedData without its '_' marker");
      // Only white space may come before the marker: VTK finds the data on its own way, and
      // anything else (a repeated tag, text) makes it read the headers from elsewhere.
      for (std::size_t c = k; c < underscore; ++c)
        if (text[c] != ' ' && text[c] != '\n' && text[c] != '\r' && text[c] != '\t')
          fail(path, "damaged AppendedData (text before its '_' marker)");
      doc.appended_begin = underscore + 1;
      return doc;
    }
    if (!self_closing) {
      open.push_back(index);
      if (static_cast<int>(open.size()) > kMaxXmlDepth)
        fail(path, "XML elements nested deeper than " + std::to_string(kMaxXmlDepth) + " levels");
    } else {
      doc.elements[index].text_end = k;
    }
  }
  return doc;
}

/// A non-negative decimal integer attribute, strictly parsed.
std::optional<std::uint64_t> unsigned_attribute(const Element& e, const std::string& key,
                                                const std::string& path) {
  const auto it = e.attributes.find(key);
  if (it == e.attributes.end()) return std::nullopt;
  std::string_view v = it->second;
  while (!v.empty() && v.front() == ' ') v.remove_prefix(1);
  while (!v.empty() && v.back() == ' ') v.remove_suffix(1);
  std::uint64_t value = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), value);
  if (v.empty() || r.ec != std::errc() || r.ptr != v.data() + v.size())
    fail(path, "<" + e.name + "> " + key + "=\"" + escape_text(it->second.substr(0, 40)) +
                   "\" is not a non-negative integer");
  return value;
}

std::size_t type_size(const std::string& type) {
  static const std::map<std::string, std::size_t> sizes{
      {"Int8", 1},  {"UInt8", 1},  {"Int16", 2},  {"UInt16", 2},   {"Int32", 4},
      {"UInt32", 4}, {"Int64", 8}, {"UInt64", 8}, {"Float32", 4}, {"Float64", 8},
      {"String", 1}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

/// The array data source: bytes of the file read on demand, raw or through base64.
class Source {
 public:
  Source(std::ifstream& file, std::uint64_t file_size, std::uint64_t begin, std::uint64_t end, bool base64)
      : file_(file), size_(file_size), begin_(begin), end_(std::min(end, file_size)), base64_(base64) {}

  /// Bytes of data available from `begin` (after decoding).
  [[nodiscard]] std::uint64_t available() const {
    const std::uint64_t chars = end_ > begin_ ? end_ - begin_ : 0;
    return base64_ ? chars / 4 * 3 : chars;
  }

  /// `n` decoded bytes starting at decoded byte 0, or nullopt if the file ends first.
  std::optional<std::string> read(std::size_t n) {
    const std::size_t chars = base64_ ? (n + 2) / 3 * 4 : n;
    if (begin_ + chars > end_) return std::nullopt;
    std::string raw(chars, '\0');
    file_.clear();
    file_.seekg(static_cast<std::streamoff>(begin_));
    file_.read(raw.data(), static_cast<std::streamsize>(chars));
    if (static_cast<std::size_t>(file_.gcount()) != chars) return std::nullopt;
    if (!base64_) return raw;
    std::string out;
    for (std::size_t k = 0; k + 3 < raw.size(); k += 4) {
      int v[4];
      for (int j = 0; j < 4; ++j) v[j] = raw[k + j] == '=' ? 0 : base64_value(raw[k + j]);
      if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[3] < 0) return std::nullopt;
      out.push_back(static_cast<char>((v[0] << 2) | (v[1] >> 4)));
      out.push_back(static_cast<char>(((v[1] & 15) << 4) | (v[2] >> 2)));
      out.push_back(static_cast<char>(((v[2] & 3) << 6) | v[3]));
    }
    out.resize(n);
    return out;
  }

 private:
  std::ifstream& file_;
  std::uint64_t size_;
  std::uint64_t begin_, end_;
  bool base64_;
};

struct Layout {
  bool big_endian = false;
  std::size_t header_bytes = 4;
  bool compressed = false;
};

std::uint64_t header_int(const std::string& bytes, std::size_t index, const Layout& layout) {
  std::uint64_t v = 0;
  const std::size_t n = layout.header_bytes;
  for (std::size_t j = 0; j < n; ++j) {
    const auto b = static_cast<unsigned char>(bytes[index * n + (layout.big_endian ? j : n - 1 - j)]);
    v = (v << 8) | b;
  }
  return v;
}

/// Uncompressed size of one array's data from its header; throws when the header does not
/// fit the file.
std::uint64_t data_bytes(const std::string& path, const std::string& what, Source& src,
                         const Layout& layout) {
  const std::size_t hs = layout.header_bytes;
  const std::uint64_t room = src.available();
  if (!layout.compressed) {
    const auto h = src.read(hs);
    if (!h) fail(path, what + ": data header beyond the end of the file");
    const std::uint64_t n = header_int(*h, 0, layout);
    if (n > room - hs)
      fail(path, what + ": data of " + std::to_string(n) + " bytes, but the file holds only " +
                     std::to_string(room - hs) + " after it");
    return n;
  }
  const auto h3 = src.read(3 * hs);
  if (!h3) fail(path, what + ": compression header beyond the end of the file");
  const std::uint64_t blocks = header_int(*h3, 0, layout);
  const std::uint64_t block_size = header_int(*h3, 1, layout);
  const std::uint64_t last = header_int(*h3, 2, layout);
  if (blocks > (room - 3 * hs) / hs)
    fail(path, what + ": " + std::to_string(blocks) + " compressed blocks do not fit in the file");
  if (blocks == 0) return 0;
  if (block_size == 0) fail(path, what + ": compressed block size 0");
  if (last > block_size)
    fail(path, what + ": last block of " + std::to_string(last) + " bytes is larger than the block size " +
                   std::to_string(block_size));
  const auto h = src.read((3 + blocks) * hs);
  if (!h) fail(path, what + ": compression header beyond the end of the file");
  std::uint64_t compressed = 0, total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t c = header_int(*h, 3 + b, layout);
    const std::uint64_t u = (b + 1 == blocks && last != 0) ? last : block_size;
    if (c > room) fail(path, what + ": compressed block of " + std::to_string(c) + " bytes is larger than the file");
    compressed += c;
    if (u > kMaxCompressionRatio * c + 1024)
      fail(path, what + ": block of " + std::to_string(u) + " bytes cannot come from " +
                     std::to_string(c) + " compressed bytes");
    total += u;
  }
  if (compressed > room - (3 + blocks) * hs)
    fail(path, what + ": compressed data of " + std::to_string(compressed) +
                   " bytes runs past the end of the file");
  return total;
}

}  // namespace

void check_xml_nesting(const std::string& path, std::string_view text) {
  try {
    parse_structure(path, text, false);
  } catch (const InputError& e) {
    // Only the depth is this check's business; other damage is the XML parser's to report.
    if (std::string(e.what()).find("nested deeper") != std::string::npos) throw;
  }
}

void check_vtu_file(const std::string& path) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) fail(path, "cannot read the file (" + ec.message() + ")");
  std::ifstream file(path, std::ios::binary);
  if (!file) fail(path, "cannot open the file");
  // The XML part: up to the appended data (or the whole file).
  std::string text;
  {
    constexpr std::size_t chunk = 1 << 16;
    std::string buffer(chunk, '\0');
    while (file.read(buffer.data(), chunk) || file.gcount() > 0) {
      const std::size_t from = text.size() > 20 ? text.size() - 20 : 0;
      text.append(buffer.data(), static_cast<std::size_t>(file.gcount()));
      const std::size_t at = text.find("<AppendedData", from);
      if (at != std::string::npos) {
        // Keep reading to the '_' marker (a few bytes on).
        const std::size_t marker = text.find('_', at);
        if (marker != std::string::npos) break;
      }
    }
  }
  const Document doc = parse_structure(path, text, true);
  if (doc.elements.empty() || doc.elements[0].name != "VTKFile") fail(path, "not a VTK XML file (no <VTKFile>)");
  const Element& root = doc.elements[0];
  const auto attr = [](const Element& e, const std::string& key) -> std::string {
    const auto it = e.attributes.find(key);
    return it == e.attributes.end() ? std::string() : it->second;
  };
  if (attr(root, "type") != "UnstructuredGrid")
    fail(path, "not an unstructured grid (VTKFile type=\"" + escape_text(attr(root, "type").substr(0, 40)) + "\")");
  Layout layout;
  const std::string order = attr(root, "byte_order");
  if (order == "BigEndian") layout.big_endian = true;
  else if (!order.empty() && order != "LittleEndian")
    fail(path, "unknown byte_order=\"" + escape_text(order.substr(0, 40)) + "\"");
  const std::string header = attr(root, "header_type");
  if (header == "UInt64") layout.header_bytes = 8;
  else if (!header.empty() && header != "UInt32")
    fail(path, "unknown header_type=\"" + escape_text(header.substr(0, 40)) + "\"");
  const std::string compressor = attr(root, "compressor");
  if (!compressor.empty()) {
    if (compressor != "vtkZLibDataCompressor" && compressor != "vtkLZ4DataCompressor" &&
        compressor != "vtkLZMADataCompressor")
      fail(path, "unknown compressor=\"" + escape_text(compressor.substr(0, 40)) + "\"");
    layout.compressed = true;
  }
  if (!doc.appended_encoding.empty() && doc.appended_encoding != "raw" && doc.appended_encoding != "base64")
    fail(path, "unknown AppendedData encoding=\"" + escape_text(doc.appended_encoding.substr(0, 40)) + "\"");
  const bool appended_base64 = doc.appended_encoding == "base64";

  // Ancestors by name, to place each DataArray.
  const auto ancestor = [&](int e, const std::string& name) {
    for (int p = doc.elements[static_cast<std::size_t>(e)].parent; p >= 0; p = doc.elements[static_cast<std::size_t>(p)].parent)
      if (doc.elements[static_cast<std::size_t>(p)].name == name) return p;
    return -1;
  };
  std::map<int, std::pair<std::uint64_t, std::uint64_t>> pieces;  // element -> (points, cells)
  for (std::size_t i = 0; i < doc.elements.size(); ++i) {
    const Element& e = doc.elements[i];
    if (e.name != "Piece") continue;
    const auto np = unsigned_attribute(e, "NumberOfPoints", path);
    const auto nc = unsigned_attribute(e, "NumberOfCells", path);
    if (!np || !nc) fail(path, "<Piece> without NumberOfPoints and NumberOfCells");
    pieces[static_cast<int>(i)] = {*np, *nc};
  }
  std::map<std::pair<int, std::string>, int> seen;  // (parent element, name) -> count
  for (std::size_t i = 0; i < doc.elements.size(); ++i) {
    const Element& e = doc.elements[i];
    if (e.name != "DataArray" && e.name != "Array") continue;
    const std::string name = attr(e, "Name");
    const std::string what = "array '" + escape_text(name.substr(0, 60)) + "'";
    // VTK's reader keeps one slot per element but replaces arrays of the same name: a
    // repeated name leaves it reading into a slot that does not exist.
    if (++seen[{e.parent, name}] > 1)
      fail(path, what + " appears twice in <" + doc.elements[static_cast<std::size_t>(std::max(e.parent, 0))].name + ">");
    const std::string type = attr(e, "type");
    const std::size_t tsize = type_size(type);
    if (tsize == 0) fail(path, what + ": unknown type=\"" + escape_text(type.substr(0, 40)) + "\"");
    const std::uint64_t components = unsigned_attribute(e, "NumberOfComponents", path).value_or(1);
    if (components < 1 || components > 1024)
      fail(path, what + ": NumberOfComponents=" + std::to_string(components) + " (expected 1 to 1024)");
    // Values the header promises, where it says.
    const int piece = ancestor(static_cast<int>(i), "Piece");
    std::optional<std::uint64_t> values;
    std::string basis;
    const int parent = e.parent;
    const std::string group = parent >= 0 ? doc.elements[static_cast<std::size_t>(parent)].name : "";
    if (piece >= 0 && pieces.count(piece)) {
      const auto [np, nc] = pieces[piece];
      if (group == "Points") {
        if (components != 3) fail(path, what + ": points need NumberOfComponents=3");
        values = np * 3;
        basis = "NumberOfPoints=" + std::to_string(np);
      } else if (group == "PointData") {
        values = np * components;
        basis = "NumberOfPoints=" + std::to_string(np);
      } else if (group == "CellData") {
        values = nc * components;
        basis = "NumberOfCells=" + std::to_string(nc);
      } else if (group == "Cells" && (name == "offsets" || name == "types")) {
        values = nc;
        basis = "NumberOfCells=" + std::to_string(nc);
      }
      if (np > (std::uint64_t{1} << 40) || nc > (std::uint64_t{1} << 40))
        fail(path, "<Piece> NumberOfPoints=" + std::to_string(np) + " NumberOfCells=" + std::to_string(nc) + " is beyond any frame");
    }
    if (!values && type != "String") {
      if (const auto tuples = unsigned_attribute(e, "NumberOfTuples", path)) {
        if (*tuples > (std::uint64_t{1} << 40)) fail(path, what + ": NumberOfTuples=" + std::to_string(*tuples));
        values = *tuples * components;
        basis = "NumberOfTuples=" + std::to_string(*tuples);
      }
    }
    const std::string format = attr(e, "format");
    std::optional<std::uint64_t> bytes;
    if (format == "appended") {
      if (!doc.appended_begin) fail(path, what + ": format=\"appended\" but the file has no AppendedData");
      const auto offset = unsigned_attribute(e, "offset", path);
      if (!offset) fail(path, what + ": format=\"appended\" without an offset");
      if (*offset >= size) fail(path, what + ": offset " + std::to_string(*offset) + " is beyond the end of the file");
      Source src(file, size, *doc.appended_begin + *offset, size, appended_base64);
      bytes = data_bytes(path, what, src, layout);
    } else if (format == "binary") {
      std::size_t b = e.text_begin;
      while (b < e.text_end && (text[b] == ' ' || text[b] == '\n' || text[b] == '\r' || text[b] == '\t')) ++b;
      Source src(file, size, b, e.text_end, true);
      bytes = data_bytes(path, what, src, layout);
    } else if (format == "ascii" || format.empty()) {
      // Every value needs at least one character and a separator.
      const std::uint64_t chars = e.text_end > e.text_begin ? e.text_end - e.text_begin : 0;
      if (values && *values > chars / 2 + 1)
        fail(path, what + ": " + basis + " needs " + std::to_string(*values) +
                       " values, more than the ascii data can hold");
    } else {
      fail(path, what + ": unknown format=\"" + escape_text(format.substr(0, 40)) + "\"");
    }
    if (type == "String") {
      // Each string takes at least its terminating NUL.
      const auto tuples = unsigned_attribute(e, "NumberOfTuples", path).value_or(0);
      const std::uint64_t room = bytes ? *bytes : (e.text_end > e.text_begin ? e.text_end - e.text_begin : 0);
      if (tuples * components > room)
        fail(path, what + ": NumberOfTuples=" + std::to_string(tuples) + " strings cannot fit in " +
                       std::to_string(room) + " bytes");
    }
    if (bytes) {
      if (type != "String" && *bytes % tsize != 0)
        fail(path, what + ": " + std::to_string(*bytes) + " bytes is not a whole number of " + type + " values");
      if (values && type != "String" && *bytes / tsize != *values)
        fail(path, what + " holds " + std::to_string(*bytes / tsize) + " values, but " + basis +
                       " makes " + std::to_string(*values));
    }
  }
}

void check_grid(const std::string& path, vtkUnstructuredGrid* grid) {
  vtkCellArray* cells = grid->GetCells();
  const vtkIdType points = grid->GetNumberOfPoints();
  if (!cells) return;
  vtkDataArray* offsets = cells->GetOffsetsArray();
  vtkDataArray* ids = cells->GetConnectivityArray();
  if (!offsets || !ids) return;
  const vtkIdType n = offsets->GetNumberOfTuples();
  const vtkIdType m = ids->GetNumberOfTuples();
  double previous = 0.0;
  for (vtkIdType k = 0; k < n; ++k) {
    const double o = offsets->GetComponent(k, 0);
    if ((k == 0 && o != 0.0) || o < previous || o > static_cast<double>(m))
      fail(path, "cell offsets are damaged (offset " + std::to_string(k) + ")");
    previous = o;
  }
  if (n > 0 && previous != static_cast<double>(m))
    fail(path, "cell offsets do not cover the connectivity");
  for (vtkIdType k = 0; k < m; ++k) {
    const double id = ids->GetComponent(k, 0);
    if (!(id >= 0.0 && id < static_cast<double>(points)))
      fail(path, "cell connectivity refers to point " + std::to_string(static_cast<long long>(id)) +
                     ", which does not exist");
  }
}

namespace {

std::string number_text(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

/// Throws unless every value of `array` passes `ok`; `expected` says what passes.
template <typename Ok>
void check_array(const std::string& path, const std::string& what, vtkDataArray* array, Ok ok,
                 const std::string& expected) {
  const int nc = array->GetNumberOfComponents();
  const vtkIdType nt = array->GetNumberOfTuples();
  for (vtkIdType t = 0; t < nt; ++t) {
    for (int c = 0; c < nc; ++c) {
      const double v = array->GetComponent(t, c);
      if (!ok(v)) {
        fail(path, what + " holds " + number_text(v) + " at tuple " + std::to_string(t) +
                       (nc > 1 ? ", component " + std::to_string(c) : std::string()) + " (" +
                       expected + ")");
      }
    }
  }
}

}  // namespace

void check_frame_values(const std::string& path, vtkUnstructuredGrid* grid) {
  const auto finite = [](double v) { return std::isfinite(v); };
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0; };
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (grid->GetPoints() && grid->GetPoints()->GetData())
    check_array(path, "the 'Points' array", grid->GetPoints()->GetData(), finite,
                "expected a finite number");
  vtkAbstractArray* names = grid->GetFieldData()->GetAbstractArray("body_names");
  const vtkIdType bodies = names && !vtkDataArray::SafeDownCast(names) ? names->GetNumberOfValues() : -1;
  const auto check_group = [&](vtkFieldData* data, const std::string& kind) {
    for (int k = 0; k < data->GetNumberOfArrays(); ++k) {
      vtkDataArray* array = vtkDataArray::SafeDownCast(data->GetAbstractArray(k));
      if (!array || !array->GetName()) continue;
      const std::string name = array->GetName();
      const std::string what = kind + " array '" + escape_text(name.substr(0, 60)) + "'";
      if (kind == "point" && (name == "radius" || name == "mass")) {
        check_array(path, what, array, positive, "expected a finite number > 0");
      } else if ((kind == "point" && (name == "cell_area" || name == "ring_radius")) ||
                 (kind == "field" && (name == "thickness" || name == "p_max"))) {
        check_array(path, what, array, non_negative, "expected a finite number >= 0");
        if (name == "p_max" && array->GetNumberOfValues() > 0 &&
            !std::isfinite(1.0 / array->GetComponent(0, 0)) && array->GetComponent(0, 0) != 0)
          fail(path, what + " holds " + number_text(array->GetComponent(0, 0)) +
                         " (too small: 1/p_max overflows)");
      } else if (kind == "cell" && name == "state") {
        check_array(path, what, array, [](double v) { return v >= 0 && v <= 5 && v == std::floor(v); },
                    "expected an integer code 0 to 5");
      } else if (kind == "point" && name == "body") {
        check_array(path, what, array,
                    [&](double v) {
                      return v >= 0 && v == std::floor(v) && v <= 2147483647.0 &&
                             (bodies < 0 || v < static_cast<double>(bodies));
                    },
                    bodies < 0 ? std::string("expected a body index >= 0")
                               : "expected a body index 0 to " + std::to_string(bodies - 1) +
                                     ": the frame names " + std::to_string(bodies) + " bodies");
      } else {
        check_array(path, what, array, finite, "expected a finite number");
      }
    }
  };
  check_group(grid->GetPointData(), "point");
  check_group(grid->GetCellData(), "cell");
  check_group(grid->GetFieldData(), "field");
}

}  // namespace hexdem::post
