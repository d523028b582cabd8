#!/usr/bin/env bash
# The quick start's entry point.
#   ./build.sh demo [colony run options]   install what is missing, build, run the demo experiment
#   ./build.sh test                        install what is missing, build, run every test
#   ./build.sh build                       install what is missing, build
#   ./build.sh sanitize                    install clang, then: the test suite under AddressSanitizer +
#                                          UndefinedBehaviorSanitizer, the loader fuzzer, and the
#                                          multi-threaded tests under ThreadSanitizer (CI's last stage;
#                                          tests/sanitizers/README.md)
# Installs missing Debian packages when run as root (or through sudo).
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(g++ make cmake pkg-config python3 libeigen3-dev libtinyxml2-dev libpng-dev libgtest-dev
          libbox2d-dev libode-dev nlohmann-json3-dev libosmesa6-dev libassimp-dev libopenmpi-dev openmpi-bin
          liblua5.3-dev libcli11-dev libhdf5-dev nettle-dev gnuplot-nox libwebsocketpp-dev libasio-dev libjs-three
          chromium python3-h5py python3-pandas python3-dev python3-numpy pybind11-dev python3-pytest python3-matplotlib)
SANITIZE_PACKAGES=(clang libclang-rt-dev)
BUILD_DIR=${COLONY_BUILD_DIR:-build}

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}" "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "Installing missing Debian packages: ${missing[*]}"
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null; then
      sudo=(sudo)
    else
      echo "Missing packages: ${missing[*]}. Install them as root: apt-get install -y ${missing[*]}" >&2
      exit 1
    fi
  fi
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"
}

build() {
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$BUILD_DIR" -j2
}

command=${1:-}
[ $# -gt 0 ] && shift
case "$command" in
  demo)
    install_missing
    build
    echo
    echo "Running experiments/diffusion.xml: 120 marXbots wandering a walled arena"
    "$BUILD_DIR/bin/colony" run experiments/diffusion.xml "$@"
    ;;
  test)
    install_missing
    build
    cd "$BUILD_DIR"
    ctest --output-on-failure -j2
    ;;
  build)
    install_missing
    build
    ;;
  sanitize)
    install_missing "${SANITIZE_PACKAGES[@]}"
    exec tests/sanitizers/run.sh
    ;;
  *)
    echo "usage: ./build.sh demo|test|build|sanitize" >&2
    exit 2
    ;;
esac
