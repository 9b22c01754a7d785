#!/usr/bin/env bash
# Câmbio's front door: installs what is missing from Debian's apt registry, configures and
# builds, then runs the main job or the tests.
#
#   bash cmake/setup.sh run  [cambio run arguments...]   # the main job on the sim default
#   bash cmake/setup.sh test [ctest arguments...]        # every test
#   bash cmake/setup.sh build                            # only install and build
#
# Environment: CAMBIO_BUILD_DIR (default: build), CAMBIO_CMAKE_ARGS (extra configure arguments,
# quoted as in a shell, e.g. -DCAMBIO_WARNINGS_AS_ERRORS=ON '-DCMAKE_CXX_FLAGS=-O1 -g'),
# CAMBIO_JOBS (default: all cores), CAMBIO_EXTRA_PACKAGES (more Debian packages to install with
# the rest, e.g. the sanitizer and fuzzing stages' clang in .ci/run).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${CAMBIO_BUILD_DIR:-$root/build}
jobs=${CAMBIO_JOBS:-$(nproc)}
mode=${1:-build}
[ $# -gt 0 ] && shift

# Everything comes from Debian 12's own packages.
packages=(
  g++ cmake make pkg-config git
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev
  libmujoco-dev libqhull-dev
  libegl-dev libopengl-dev libgl-dev libgl1-mesa-dri libegl-mesa0
  libopencv-dev libpng-dev libjpeg62-turbo-dev
  libvisp-vs-dev libvisp-visual-features-dev libvisp-core-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libplplot-dev plplot-driver-cairo
  cyclonedds-dev cyclonedds-tools rosidl-tools python3-rosidl python3-catkin-pkg python3-empy
  liburdfdom-tools
  clang-format
)
if [ -n "${CAMBIO_EXTRA_PACKAGES:-}" ]; then
  read -r -a extra_packages <<<"$CAMBIO_EXTRA_PACKAGES"
  packages+=("${extra_packages[@]}")
fi

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing from apt: ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install packages" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=300 update -q
  "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=300 install -y -q --no-install-recommends "${missing[@]}"
fi

# CAMBIO_CMAKE_ARGS split as a shell would (xargs honours its quotes), never evaluated.
cmake_args=()
if [ -n "${CAMBIO_CMAKE_ARGS:-}" ]; then
  mapfile -t cmake_args < <(xargs printf '%s\n' <<<"$CAMBIO_CMAKE_ARGS")
fi
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "${cmake_args[@]}" >/dev/null
cmake --build "$build_dir" -j "$jobs"

case "$mode" in
  build) ;;
  run)
    if [ $# -eq 0 ]; then
      set -- "$root/firmware_config/experiments/vergence_sphere.yaml" --out "$root/out"
    fi
    "$build_dir/bin/cambio" run "$@"
    ;;
  test)
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@"
    ;;
  *)
    echo "usage: bash cmake/setup.sh run|test|build [arguments...]" >&2
    exit 2
    ;;
esac
