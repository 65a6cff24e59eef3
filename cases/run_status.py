"""The status of a finished `hexdem run`, for the analysis scripts of the cases.

`hexdem run` writes `<case>.status` next to `<case>.pvd`: `running` while it runs, then
`completed`, or `failed: <reason>` after a numerical blow-up or an energy balance failure
(docs/file-format.md). A series that did not complete is truncated and its numbers mean
nothing: the scripts refuse it with one line and exit code 2.
"""
import os
import sys


def status(series):
    """The status line of the run that wrote `series` (its .pvd, or any of its CSVs)."""
    stem = series
    for suffix in (".pvd", ".energy.csv", ".bodies.csv", ".probes.csv"):
        if stem.endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    path = stem + ".status"
    try:
        with open(path) as f:
            return f.readline().strip(), path
    except OSError as e:
        return "missing (%s)" % (e.strerror or e), path


def require_completed(series, program=None):
    """Exits with code 2 and one line on stderr unless the run of `series` completed."""
    line, path = status(series)
    if line != "completed":
        name = program or os.path.basename(sys.argv[0])
        print("%s: %s: the run did not complete (%s: %s); refusing to analyse a truncated series"
              % (name, series, path, line), file=sys.stderr)
        sys.exit(2)
