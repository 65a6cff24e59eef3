#!/usr/bin/env bash
# scripts/setup-deps.sh installs the ParaView GUI and its SVG icon support, and the GUI starts.
#   test_gui_deps.sh SOURCE_DIR
set -u
src=$1
fail() { echo "FAIL: $*"; exit 1; }
setup=$src/scripts/setup-deps.sh
# The package list (the lines between "packages=(" and ")"), one name a line, comments dropped.
list=$(sed -n '/^packages=(/,/^)/p' "$setup" | sed 's/#.*//' | tr -s ' \t()' '\n')
for p in paraview libqt5svg5 paraview-dev python3-paraview xvfb; do
  grep -qx -- "$p" <<<"$list" || fail "setup-deps.sh does not install $p"
done
"$setup" --check || fail "setup-deps.sh --check: packages missing on this machine"
# Qt's SVG image plugin (libqt5svg5): without it the GUI's toolbar icons are blank.
dpkg -L libqt5svg5 | grep -q 'imageformats/libqsvg.so' || fail "libqt5svg5 has no libqsvg.so"
version=$(xvfb-run -a -s "-screen 0 1280x1024x24" paraview --version 2>/dev/null)
grep -q "paraview version 5.11" <<<"$version" || fail "paraview --version: '$version'"
echo "OK: $version"
