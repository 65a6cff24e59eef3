#!/usr/bin/env bash
# Installs what is missing, builds hexdem, and runs the whole test suite:
#   1. the Release build: every ctest test (labels fast, cli, validation);
#   2. the ASan+UBSan build: the fast tests.
# Usage (as root on Debian 12): scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

scripts/setup-deps.sh

echo "== Release build"
scripts/build.sh release
echo "== Release tests"
ctest --preset release -j "$jobs"

echo "== ASan+UBSan build"
scripts/build.sh asan
echo "== ASan+UBSan tests (label fast)"
ctest --preset asan -j "$jobs" -L fast
