#!/usr/bin/python3
"""Writes the DXF drawings used by tests/meshing/test_outline_dxf.cpp.

Usage: make_dxf_fixtures.py OUTDIR

The drawings are written with ezdxf, a writer independent of the reader under test (dxflib).
The equivalent geometry of each drawing is documented next to it, in drawing units; the
reader scales by $INSUNITS (4 = mm, 6 = m, 0 or absent = 1 unit per metre).

  a_rect_lwpolyline.dxf  mm. One closed LWPOLYLINE on layer 'rim':
                         rectangle (10,5) (50,5) (50,25) (10,25). Area 800 mm^2.
  b_rect_lines.dxf       mm. The rectangle of (a) as 4 LINEs on layers 'bottom' (y = 5),
                         'right' (x = 50), 'top' (y = 25), 'left' (x = 10), written in the
                         order top, left, bottom, right with top and bottom reversed.
                         Equivalent TOML: min = [0.010, 0.005], max = [0.050, 0.025] m.
  c_bulge.dxf            mm. Closed LWPOLYLINE on layer 'outline': (0,0) (40,0) bulge +1
                         (40,20) (0,20): a 40 x 20 rectangle whose right side is a
                         semicircle of radius 10 about (40,10) reaching x = 50.
                         Area 800 + 50 pi mm^2.
  d_disk_hole.dxf        mm. CIRCLE on layer 'rim', centre (0,0), radius 20; closed
                         LWPOLYLINE on layer 'hole': square (-5,-5) .. (5,5).
                         One body: outer area 400 pi, hole area 100 mm^2.
  e_two_bodies.dxf       mm. Closed LWPOLYLINEs on layer '0': rectangle (0,0) .. (10,10)
                         (listed first) and rectangle (20,0) .. (50,10). body1 is the larger
                         (area 300), body2 the smaller (area 100).
  f_open_chain.dxf       mm. LINEs on layer 'edge': (0,0)-(10,0), (10,0)-(10,5),
                         (10,5)-(0,5). The chain ends at (0,0) and (0,5): an error.
  g_skipped_types.dxf    mm. The rectangle (0,0) .. (20,10) as a closed LWPOLYLINE on layer
                         'body', plus 1 SPLINE, 2 TEXT, 3 POINT, 1 INSERT of block 'bolt'
                         (whose definition holds a CIRCLE and an open LINE) and an open LINE
                         in paper space. Only the rectangle is read.
  h_arc_lines.dxf        unitless ($INSUNITS = 0). Rectangle (0,0) .. (30,20) with the
                         top-right corner rounded: LINEs (0,0)-(30,0), (30,12)-(30,0) on
                         layer 'side', ARC on layer 'fillet' about (22,12), radius 8, from
                         0 to 90 degrees, LINEs (0,20)-(22,20), (0,0)-(0,20) on layer 'side'.
                         Area 536 + 16 pi.
  i_polyline_r12.dxf     R12, no $INSUNITS (metres). Classic 2D POLYLINE, closed, layer
                         'shell', clockwise: (0,0) (0,0.01) (0.02,0.01) bulge -1 (0.02,0):
                         a 0.02 x 0.01 rectangle whose right side is a semicircle of radius
                         0.005 about (0.02,0.005) reaching x = 0.025.
                         Area 2e-4 + pi 2.5e-5 / 2 m^2.
  j_island.dxf           mm. Closed LWPOLYLINEs on layer '0': squares (0,0) .. (100,100),
                         (20,20) .. (80,80) and (40,40) .. (60,60). body1 = the big square
                         with the middle one as its hole; body2 = the island (40,40) .. (60,60).
  k_branch.dxf           mm. LINEs on layer 'web': the rectangle (0,0) .. (10,5) plus the
                         diagonal (0,0)-(10,5): three ends meet at (0,0). An error.
  l_arc_mirrored.dxf     Same geometry as (h), but the ARC has extrusion (0,0,-1): its
                         centre and angles are given in the mirrored object coordinate
                         system (centre (-22,12), 90 to 180 degrees).
  empty.dxf              An empty file.
  not_dxf.dxf            A text file that is not DXF.
  fixtures.stamp         Written after all the drawings.
"""

import os
import sys

import ezdxf
from ezdxf.math import OCS

MM = 4
UNITLESS = 0


def save(doc, out, name):
    """Writes atomically, so that test processes running side by side never read a partial file."""
    tmp = os.path.join(out, "%s.%d.tmp" % (name, os.getpid()))
    doc.saveas(tmp)
    os.replace(tmp, os.path.join(out, name))


def save_text(out, name, text):
    tmp = os.path.join(out, "%s.%d.tmp" % (name, os.getpid()))
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, os.path.join(out, name))


def new_doc(units, version="R2010"):
    doc = ezdxf.new(version)
    doc.header["$INSUNITS"] = units
    return doc


def add_closed(msp, points, layer):
    msp.add_lwpolyline(points, format="xy", close=True, dxfattribs={"layer": layer})


def rect(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def make_a(out):
    doc = new_doc(MM)
    add_closed(doc.modelspace(), rect(10, 5, 50, 25), "rim")
    save(doc, out, "a_rect_lwpolyline.dxf")


def make_b(out):
    doc = new_doc(MM)
    msp = doc.modelspace()
    msp.add_line((10, 25), (50, 25), dxfattribs={"layer": "top"})      # reversed
    msp.add_line((10, 25), (10, 5), dxfattribs={"layer": "left"})
    msp.add_line((50, 5), (10, 5), dxfattribs={"layer": "bottom"})     # reversed
    msp.add_line((50, 5), (50, 25), dxfattribs={"layer": "right"})
    save(doc, out, "b_rect_lines.dxf")


def make_c(out):
    doc = new_doc(MM)
    doc.modelspace().add_lwpolyline(
        [(0, 0, 0), (40, 0, 1.0), (40, 20, 0), (0, 20, 0)], format="xyb", close=True,
        dxfattribs={"layer": "outline"})
    save(doc, out, "c_bulge.dxf")


def make_d(out):
    doc = new_doc(MM)
    msp = doc.modelspace()
    msp.add_circle((0, 0), 20, dxfattribs={"layer": "rim"})
    add_closed(msp, rect(-5, -5, 5, 5), "hole")
    save(doc, out, "d_disk_hole.dxf")


def make_e(out):
    doc = new_doc(MM)
    msp = doc.modelspace()
    add_closed(msp, rect(0, 0, 10, 10), "0")
    add_closed(msp, rect(20, 0, 50, 10), "0")
    save(doc, out, "e_two_bodies.dxf")


def make_f(out):
    doc = new_doc(MM)
    msp = doc.modelspace()
    for a, b in [((0, 0), (10, 0)), ((10, 0), (10, 5)), ((10, 5), (0, 5))]:
        msp.add_line(a, b, dxfattribs={"layer": "edge"})
    save(doc, out, "f_open_chain.dxf")


def make_g(out):
    doc = new_doc(MM)
    block = doc.blocks.new(name="bolt")
    block.add_circle((0, 0), 1)
    block.add_line((0, 0), (3, 0))
    msp = doc.modelspace()
    add_closed(msp, rect(0, 0, 20, 10), "body")
    msp.add_spline([(0, 12), (5, 14), (10, 12), (15, 14)], dxfattribs={"layer": "notes"})
    msp.add_text("hexdem", dxfattribs={"layer": "notes", "insert": (0, -5), "height": 2})
    msp.add_text("fixture", dxfattribs={"layer": "notes", "insert": (0, -8), "height": 2})
    for x in (1.0, 2.0, 3.0):
        msp.add_point((x, -10), dxfattribs={"layer": "notes"})
    msp.add_blockref("bolt", (5, 5))
    doc.layout("Layout1").add_line((0, 0), (100, 0))
    save(doc, out, "g_skipped_types.dxf")


def make_h(out, mirrored):
    doc = new_doc(UNITLESS)
    msp = doc.modelspace()
    side = {"layer": "side"}
    msp.add_line((0, 0), (30, 0), dxfattribs=side)
    msp.add_line((30, 12), (30, 0), dxfattribs=side)
    if mirrored:
        ocs = OCS((0, 0, -1))
        centre = ocs.from_wcs((22, 12, 0))
        # In the mirrored system the WCS arc from (30,12) to (22,20) runs counter-clockwise
        # from (-22,20) at 90 degrees to (-30,12) at 180 degrees.
        msp.add_arc(centre, 8, 90, 180, dxfattribs={"layer": "fillet", "extrusion": (0, 0, -1)})
    else:
        msp.add_arc((22, 12), 8, 0, 90, dxfattribs={"layer": "fillet"})
    msp.add_line((0, 20), (22, 20), dxfattribs=side)
    msp.add_line((0, 0), (0, 20), dxfattribs=side)
    name = "l_arc_mirrored.dxf" if mirrored else "h_arc_lines.dxf"
    save(doc, out, name)


def make_i(out):
    doc = ezdxf.new("R12")
    if "$INSUNITS" in doc.header:
        del doc.header["$INSUNITS"]
    pts = [(0.0, 0.0, 0.0), (0.0, 0.01, 0.0), (0.02, 0.01, -1.0), (0.02, 0.0, 0.0)]
    poly = doc.modelspace().add_polyline2d([(x, y) for x, y, _ in pts], close=True,
                                           dxfattribs={"layer": "shell"})
    for vertex, (_, _, bulge) in zip(poly.vertices, pts):
        vertex.dxf.bulge = bulge
    save(doc, out, "i_polyline_r12.dxf")


def make_j(out):
    doc = new_doc(MM)
    msp = doc.modelspace()
    for a, b in [(0, 100), (20, 80), (40, 60)]:
        add_closed(msp, rect(a, a, b, b), "0")
    save(doc, out, "j_island.dxf")


def make_k(out):
    doc = new_doc(MM)
    msp = doc.modelspace()
    pts = rect(0, 0, 10, 5)
    for k in range(4):
        msp.add_line(pts[k], pts[(k + 1) % 4], dxfattribs={"layer": "web"})
    msp.add_line((0, 0), (10, 5), dxfattribs={"layer": "web"})
    save(doc, out, "k_branch.dxf")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: make_dxf_fixtures.py OUTDIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    make_a(out)
    make_b(out)
    make_c(out)
    make_d(out)
    make_e(out)
    make_f(out)
    make_g(out)
    make_h(out, mirrored=False)
    make_h(out, mirrored=True)
    make_i(out)
    make_j(out)
    make_k(out)
    save_text(out, "empty.dxf", "")
    save_text(out, "not_dxf.dxf", "This is a plain text file.\nIt has two lines.\n")
    # Written last: its presence means every drawing above is complete.
    save_text(out, "fixtures.stamp", "ok\n")


if __name__ == "__main__":
    main()
