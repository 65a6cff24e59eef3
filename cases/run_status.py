"""The status of a finished `hexdem run`, for the analysis scripts of the cases.

`hexdem run` writes `<case>.status` next to `<case>.pvd`: `running` while it runs, then
`completed`, `completed with warning: <warning>` when its energy error passed
`[time] energy_warning` on the way (exit code 3), or `failed: <reason>` after a numerical
blow-up or an energy balance failure (docs/file-format.md). A series that did not complete is
truncated and its numbers mean nothing: the scripts refuse it with one line and exit code 2.
A series that completed with a warning is whole, but its numbers may be wrong: the scripts
analyse it and say so on stderr, one line.
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


WARNING = "completed with warning: "


def require_completed(series, program=None):
    """Exits with code 2 and one line on stderr unless the run of `series` completed. Returns
    the run's warning ("" if none), which it also prints on stderr as one line."""
    line, path = status(series)
    name = program or os.path.basename(sys.argv[0])
    if line.startswith(WARNING):
        warning = line[len(WARNING):]
        print("%s: %s: warning: the run completed with a warning, its numbers may be wrong: %s"
              % (name, series, warning), file=sys.stderr)
        return warning
    if line != "completed":
        print("%s: %s: the run did not complete (%s: %s); refusing to analyse a truncated series"
              % (name, series, path, line), file=sys.stderr)
        sys.exit(2)
    return ""
