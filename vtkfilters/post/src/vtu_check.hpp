#pragma once
/// \file vtu_check.hpp
/// Checks of VTK XML files before VTK reads them, and of the grid after. VTK's XML readers
/// believe a file's header: NumberOfPoints, NumberOfCells and the block sizes of compressed
/// arrays decide what they allocate and divide by, and the XML parser recurses per nesting
/// level. A damaged or hostile file then ends in SIGFPE, SIGSEGV, a stack overflow or a huge
/// allocation instead of an error. These checks compare the header with the file itself.

#include <string>
#include <string_view>

class vtkUnstructuredGrid;

namespace hexdem::post {

/// Deepest XML element nesting accepted in .vtu and .pvd files (a .vtu needs 6 levels).
inline constexpr int kMaxXmlDepth = 64;

/// Largest .pvd file read [bytes].
inline constexpr std::size_t kMaxPvdBytes = std::size_t{64} << 20;

/// Throws InputError "PATH: ..." when the XML part of `text` nests deeper than kMaxXmlDepth
/// or is not well formed enough to count (an unterminated tag).
void check_xml_nesting(const std::string& path, std::string_view text);

/// Checks a .vtu file before VTK reads it: the XML nesting; the VTKFile attributes (type
/// UnstructuredGrid, byte_order, header_type, compressor); NumberOfPoints and NumberOfCells
/// of every Piece; and, for every DataArray, that its data (appended raw or base64, inline
/// binary, or ascii) lies inside the file, that compressed block headers are consistent (no
/// block size 0, no block larger than its compressed size allows) and that the number of
/// values matches what NumberOfPoints / NumberOfCells / NumberOfTuples say. Throws
/// InputError naming the file and the problem.
void check_vtu_file(const std::string& path);

/// Checks the grid VTK read: cell offsets increasing and inside the connectivity, every
/// point id inside the points. Throws InputError naming the file.
void check_grid(const std::string& path, vtkUnstructuredGrid* grid);

/// Checks the values of a frame against the frame contract (docs/filters.md, section 1): no
/// NaN or infinite number in the points or in any numeric point, cell or field array;
/// `radius` and `mass` > 0, `cell_area`, `thickness` and `p_max` >= 0 (and 1/p_max finite);
/// `state` an integer code 0 to 5; `body` an integer index into `body_names`. Throws
/// InputError naming the file, the array and the first bad value.
void check_frame_values(const std::string& path, vtkUnstructuredGrid* grid);

}  // namespace hexdem::post
