#pragma once
/// \file outline_dxf.hpp
/// Reads an outline from a DXF drawing (LWPOLYLINE, POLYLINE, LINE, ARC, CIRCLE) through
/// dxflib. Layers name the boundary sets. Loose entities are chained into closed loops within
/// a tolerance; the outermost loops are bodies and loops inside them are their holes.
/// The header's $INSUNITS sets the unit (metres when absent); ReadOptions::scale overrides it.

#include <string>
#include <vector>

#include "hexdem/meshing/outline.hpp"
#include "hexdem/meshing/outline_toml.hpp"

namespace hexdem::meshing {

/// Reads a DXF file. Unsupported entity types are skipped; one warning line per type is
/// appended to `warnings` (if given). Throws InputError naming the file and the problem, also
/// for what dxflib would misread silently: a file without its EOF marker (truncated), a line
/// too long for dxflib or with a NUL character, an LWPOLYLINE whose vertex count (group code 90)
/// differs from its vertices, a bulge beyond 1e6, a $INSUNITS that is not an integer. When no
/// closed outline remains, the error names the skipped entities (the warnings are not printed
/// after an error).
Outline read_outline_dxf(const std::string& path, const ReadOptions& options,
                         std::vector<std::string>* warnings = nullptr);

/// Metres per drawing unit for a DXF $INSUNITS code (0 or unknown: 1).
double dxf_insunits_to_metres(int code);

}  // namespace hexdem::meshing
