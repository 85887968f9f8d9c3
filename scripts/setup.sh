#!/usr/bin/env bash
# Sets symphong up on Debian 12: installs the Debian packages it needs (only those missing, with
# apt-get, as root or through sudo; libstb-dev decodes PNG/JPEG/HDR textures; python3-matplotlib draws the plots of `symphong study`; pybind11,
# python3-dev, NumPy and pytest build and test the Python module; Open MPI runs a render across
# processes or machines; dpkg-dev, pip, setuptools and wheel make and test the Debian package and `pip install .`;
# blender runs the Blender add-on's tests)
# and builds the Release preset into
# build/release (the program build/release/symphong, the module in build/release/python).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake ninja-build g++ pkg-config
  libembree-dev libtbb-dev libopenexr-dev libpng-dev libtinyobjloader-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libpcg-cpp-dev libassimp-dev libstb-dev
  libgtest-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin
  python3-matplotlib
  pybind11-dev python3-dev python3-numpy python3-pytest
  dpkg-dev python3-pip python3-setuptools python3-wheel
  chromium chromium-driver python3-selenium  # the browser test of report.html
  blender  # the Blender add-on's tests (tests/blender, CTest label blender; Debian's Blender 3.4 runs the system python3)
)
. scripts/install-missing.sh
install_missing setup "${packages[@]}"

cmake --preset release >/dev/null
cmake --build --preset release
