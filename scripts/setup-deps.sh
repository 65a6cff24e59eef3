#!/usr/bin/env bash
# Installs the Debian 12 packages hexdem needs to build, test and render (idempotent).
# Usage: scripts/setup-deps.sh          (as root, or with sudo available)
#        scripts/setup-deps.sh --check  (installs nothing: lists the missing packages, exit 1 if any)
set -euo pipefail

# libopenmpi-dev: ParaView's CMake package checks MPI headers at configure time.
# libdeflate-dev: the .vtu writer's zlib streams (zlib1g-dev: the readers and checks).
# calculix-ccx: the finite-element reference of cases/narrow_plate (ctest case_narrow_plate_calculix).
# python3-scipy: the sparse solver of the fictitious-crack references of the notched beam and the
# Brazilian disc (cases/material_tests/fictitious_crack.py and brazilian_fe.py, ctests
# case_material_notched_beam_reference and case_material_brazilian_reference).
# paraview: the GUI the README opens results in; libqt5svg5: without it the GUI's toolbar icons
# (SVG) are blank.
packages=(
  build-essential cmake ninja-build git pkg-config
  paraview paraview-dev libopenmpi-dev python3-paraview python3-numpy xvfb xauth libqt5svg5
  libcgal-dev libeigen3-dev libgtest-dev libgmock-dev libbenchmark-dev
  libtomlplusplus-dev libcli11-dev libdxflib-dev zlib1g-dev libdeflate-dev
  python3-ezdxf python3-matplotlib python3-scipy clang-format time calculix-ccx
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "hexdem: all build dependencies present"
  exit 0
fi

if [ "${1:-}" = "--check" ]; then
  echo "hexdem: missing ${missing[*]}"
  exit 1
fi

echo "hexdem: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
