#!/usr/bin/env python3
"""Writes the meshing benchmark outline: a 1,000-vertex polygon with 10 holes of 100 vertices,
sized so that disk radius r = 1 m gives about N disks (default 1,000,000). The same shape is
built in code by tests/benchmarks/bench_lattice_generator.cpp.

    python3 scripts/make_bench_outline.py OUT.toml [N]
"""
import math
import sys


def wobbly(cx, cy, R, n, ccw):
    pts = []
    for k in range(n):
        t = 2 * math.pi * k / n * (1 if ccw else -1)
        rr = R * (1 + 0.08 * math.sin(7 * t) + 0.04 * math.sin(13 * t))
        pts.append((cx + rr * math.cos(t), cy + rr * math.sin(t)))
    return pts


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: make_bench_outline.py OUT.toml [N]")
    n = float(sys.argv[2]) if len(sys.argv) > 2 else 1e6
    R = math.sqrt(n * 2 * math.sqrt(3) / math.pi * 1.02)
    fmt = lambda pts: "[" + ", ".join(f"[{x:.9f}, {y:.9f}]" for x, y in pts) + "]"
    out = ["# Meshing benchmark outline (scripts/make_bench_outline.py)", "[lattice]", "radius = 1.0", "",
           "[[body]]", 'name = "bench"', "  [[body.shape]]", '  type = "polygon"',
           '  boundary = "rim"', "  points = " + fmt(wobbly(0, 0, R, 1000, True))]
    for h in range(10):
        a = 2 * math.pi * h / 10
        out += ["  [[body.shape]]", '  type = "polygon"', '  role = "hole"', f'  boundary = "hole{h}"',
                "  points = " + fmt(wobbly(0.6 * R * math.cos(a), 0.6 * R * math.sin(a), 0.05 * R, 100, True))]
    with open(sys.argv[1], "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
