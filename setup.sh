#!/usr/bin/env bash
# Sets up CTSplines on Debian 12: installs the apt packages it needs, configures, builds, installs
# (so that `/usr/bin/python3 -c "import ctsplines"` works) and runs the main job on the built-in
# default (`python3 -m ctsplines demo`), which writes into ./ctsplines-output.
#
#   ./setup.sh               everything
#   ./setup.sh --no-demo     stop after installing
# Environment: BUILD_DIR (default build), PREFIX (default /usr/local), JOBS (default nproc).
set -euo pipefail
cd "$(dirname "$0")"

demo=1
for arg in "$@"; do
  case "$arg" in
    --no-demo) demo=0 ;;
    *) echo "setup.sh: unknown option $arg" >&2; exit 2 ;;
  esac
done

BUILD_DIR=${BUILD_DIR:-build}
PREFIX=${PREFIX:-/usr/local}
JOBS=${JOBS:-$(nproc)}
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

packages=(
  g++ cmake ninja-build git
  paraview-dev python3-paraview
  libeigen3-dev libgtest-dev libcgal-dev
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev libtbb-dev
  python3-numpy python3-scipy python3-matplotlib python3-lz4
  xvfb xauth libgl1-mesa-dri
  # The ParaView plugin: find_package(ParaView) needs the development files of everything
  # ParaView's VTK was built against.
  qtbase5-dev qttools5-dev libqt5opengl5-dev libqt5svg5-dev qtxmlpatterns5-dev-tools
  libhdf5-openmpi-dev libopenmpi-dev libutfcpp-dev libnetcdf-dev libgdal-dev
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev libswresample-dev
  libogg-dev libtheora-dev libgl2ps-dev libx11-dev libxt-dev libglew-dev
  libdouble-conversion-dev liblz4-dev liblzma-dev libexpat1-dev libfreetype-dev
  libjpeg-dev libpng-dev libtiff-dev zlib1g-dev libxml2-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

echo "== configure and build ($BUILD_DIR)"
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$PREFIX" \
  -DPython3_EXECUTABLE=/usr/bin/python3
cmake --build "$BUILD_DIR" -j "$JOBS"

echo "== install into $PREFIX"
$SUDO cmake --install "$BUILD_DIR"
$SUDO ldconfig
/usr/bin/python3 -c "import ctsplines; print('ctsplines', ctsplines.__version__, 'from', ctsplines.__file__)"

if [ "$demo" -eq 1 ]; then
  echo "== main job: python3 -m ctsplines demo"
  xvfb-run -a /usr/bin/python3 -m ctsplines demo --output ctsplines-output
fi
