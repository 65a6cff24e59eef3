#!/usr/bin/python3
"""lattice_study.py's perforation table (--perturb as a speed sweep): counts per impact speed
and each seed's bracket of the ballistic limit, on made-up members (no run): an ordered
sweep, a seed that perforates at every speed, one that never does, and one whose slower member
perforated while a faster one did not (reported as not ordered)."""
import contextlib
import importlib.util
import io
import os
import sys
import types

HERE = os.path.dirname(os.path.abspath(__file__))
WARHEAD = os.path.join(HERE, "..", "..", "cases", "warhead")
sys.path.insert(0, WARHEAD)  # lattice_study.py imports its neighbour members.py
spec = importlib.util.spec_from_file_location("lattice_study", os.path.join(WARHEAD, "lattice_study.py"))
study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(study)


def member(seed, k, outcome, angle=0.0):
    return {"speed": 50, "radius": 0.5e-3, "angle": angle, "seed": seed, "k": k, "outcome": outcome}


def main():
    args = types.SimpleNamespace(speeds=[50], radii=[0.5e-3], angles=[0.0, 10.0], perturb=2, delta=0.1)
    P, S = "perforation", "penetrating"
    members = [member(1, k, P if k >= 1 else S) for k in range(-2, 3)]               # limit 50-55
    members += [member(2, k, P) for k in range(-2, 3)]                                # below 40
    members += [member(3, k, "rebound") for k in range(-2, 3)]                        # above 60
    members += [member(1, k, P if k in (-1, 2) else S, angle=10.0) for k in range(-2, 3)]  # not ordered
    out_text = io.StringIO()
    with contextlib.redirect_stdout(out_text):
        rows = study.perforation_table(args, members)
    text = out_text.getvalue()
    failures = []
    if len(rows) != 2:
        failures.append("expected two rows (two angles), got %d" % len(rows))
    else:
        first = rows[0]
        if first["perforated"] != [[1, 3], [1, 3], [1, 3], [2, 3], [2, 3]]:
            failures.append("counts per speed at 0 degrees: %s" % first["perforated"])
        b = first["brackets"]
        if abs(b["1"]["low"] - 50) > 1e-9 or abs(b["1"]["high"] - 55) > 1e-9 or not b["1"]["ordered"]:
            failures.append("seed 1's bracket: %s" % b["1"])
        if b["2"]["low"] is not None or abs(b["2"]["high"] - 40) > 1e-9:
            failures.append("seed 2's bracket: %s" % b["2"])
        if b["3"]["high"] is not None or abs(b["3"]["low"] - 60) > 1e-9:
            failures.append("seed 3's bracket: %s" % b["3"])
        if rows[1]["brackets"]["1"]["ordered"]:
            failures.append("a slower perforation below a faster stop must be reported as not ordered")
    # The logistic fit: symmetric data put the limit half-way; no fit without a bracket.
    fit = study.logistic_limit([(45.0, False), (45.0, False), (50.0, False), (50.0, True), (55.0, True), (55.0, True)])
    if fit is None or abs(fit - 50.0) > 0.05:
        failures.append("logistic fit of symmetric data: %s (50 expected)" % fit)
    if study.logistic_limit([(45.0, True), (50.0, True)]) is not None:
        failures.append("a fit where every member perforated")
    if rows and rows[0].get("logistic_limit") is None:
        failures.append("the 0-degree row has no logistic fit")
    for expected in ("| 50 | 0.5 | 0 | 1/3 | 1/3 | 1/3 | 2/3 | 2/3 | 1: 50-55; 2: below 40; 3: above 60 | ",
                     "1: not ordered (45 perforated, 55 did not)", "| 40 m/s | 45 m/s | 50 m/s | 55 m/s | 60 m/s |"):
        if expected not in text:
            failures.append("missing from the table: %r" % expected)
    if failures:
        print(text)
        for f in failures:
            print("FAILED: " + f)
        return 1
    print(text)
    print("perforation table: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
