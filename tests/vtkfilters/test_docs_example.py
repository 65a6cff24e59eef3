"""The pvpython example of docs/filters.md (section 5), run as it stands in the docs.

    python3 test_docs_example.py DOCS.md INTERPRETER FRAMES_DIR PLUGIN.so WORK_DIR

The code block that follows the marker `<!-- docs-example: pvpython -->` is written to
WORK_DIR/script.py unchanged and run by INTERPRETER (pvpython or pvbatch) in WORK_DIR, where
`run.pvd` is a copy of the test series (3 frames: 1, 2 and 3 fragments) and
`build/release/lib/paraview-5.11/plugins/HexDEMFilters/HexDEMFilters.so` is a link to the
plugin under test. PV_PLUGIN_PATH is removed from the environment: the script must load the
plugin itself, as a user's would.
"""

import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

MARKER = "<!-- docs-example: pvpython -->"
PLUGIN = "build/release/lib/paraview-5.11/plugins/HexDEMFilters/HexDEMFilters.so"


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def extract(docs):
    """The indented block after the marker, de-indented by 4 spaces."""
    with open(docs, encoding="utf-8") as f:
        lines = f.read().split("\n")
    try:
        start = lines.index(MARKER) + 1
    except ValueError:
        fail("%s: no line %r" % (docs, MARKER))
    while start < len(lines) and not lines[start].strip():
        start += 1
    block = []
    for line in lines[start:]:
        if line.strip() and not line.startswith("    "):
            break
        block.append(line[4:])
    while block and not block[-1].strip():
        block.pop()
    if not block:
        fail("%s: no code block after %r" % (docs, MARKER))
    return "\n".join(block) + "\n"


def main():
    docs, interpreter, frames, plugin, work = sys.argv[1:6]
    script = extract(docs)
    if PLUGIN not in script:
        fail("the example no longer loads %s; update this test" % PLUGIN)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, os.path.dirname(PLUGIN)))
    os.symlink(os.path.abspath(plugin), os.path.join(work, PLUGIN))
    series = os.path.join(frames, "series.pvd")
    for data_set in ET.parse(series).getroot().iter("DataSet"):
        name = data_set.get("file")
        os.makedirs(os.path.join(work, os.path.dirname(name)), exist_ok=True)
        shutil.copy(os.path.join(frames, name), os.path.join(work, name))
    shutil.copy(series, os.path.join(work, "run.pvd"))
    with open(os.path.join(work, "script.py"), "w", encoding="utf-8") as f:
        f.write(script)

    env = dict(os.environ)
    env.pop("PV_PLUGIN_PATH", None)
    run = subprocess.run([interpreter, "script.py"], cwd=work, env=env, capture_output=True,
                         text=True, timeout=240)
    sys.stdout.write(run.stdout)
    sys.stdout.write(run.stderr)
    if run.returncode != 0:
        fail("%s script.py exited with %d" % (interpreter, run.returncode))
    if "Traceback" in run.stderr or "Error" in run.stderr:
        fail("errors on stderr")
    rows = re.findall(r"^t = (\S+) s: max_shear (\S+) Pa, (\d+) broken bonds, (\d+) fragments$",
                      run.stdout, re.M)
    if len(rows) != 3:
        fail("expected 3 frames printed, got %d" % len(rows))
    fragments = [int(r[3]) for r in rows]
    cracks = [int(r[2]) for r in rows]
    if fragments != [1, 2, 3]:
        fail("fragment counts %s, expected [1, 2, 3]" % fragments)
    if not (cracks[0] == 0 and 0 < cracks[1] < cracks[2]):
        fail("crack counts %s: expected 0, then growing" % cracks)
    if not all(float(r[1]) >= 0 for r in rows):
        fail("negative max_shear")
    print("OK: the docs' pvpython example runs in %s" % os.path.basename(interpreter))


if __name__ == "__main__":
    main()
