#!/usr/bin/env bash
# taskmap developer entry point: the two commands of README.md and their parts.
#   tools/dev.sh main    install what is missing, build, build the basket task map, show it
#   tools/dev.sh test    install what is missing, build, run every test (release, install +
#                        consumer, sanitizer build of the unit tests)
#   tools/dev.sh deps | build | bench
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${TASKMAP_BUILD_DIR:-$ROOT/build}"
ASAN_BUILD="${TASKMAP_ASAN_BUILD_DIR:-$ROOT/build-asan}"
JOBS="${TASKMAP_JOBS:-$(nproc)}"

# Debian packages the project needs (one list: the set-up stays one step).
PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache git clang-format
  libeigen3-dev libbullet-dev libflann-dev liblz4-dev libassimp-dev libcgal-dev libgmp-dev libmpfr-dev
  libhdf5-dev libqhull-dev liburdfdom-dev libtinyxml-dev libssl-dev
  googletest libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
  pybind11-dev python3 python3-dev python3-venv python3-numpy python3-h5py python3-scipy python3-fastcluster
  libnanoflann-dev libcairo2-dev fonts-dejavu-core openmpi-bin libopenmpi-dev
  liborocos-kdl-dev libfcl-dev libmujoco-dev
  chromium libjs-three
  doxygen python3-sphinx
)

log() { printf '\n== %s\n' "$*"; }

deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    log "dependencies: all ${#PACKAGES[@]} Debian packages present"
    return
  fi
  log "dependencies: installing ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "tools/dev.sh: need root (or sudo) to apt-get install: ${missing[*]}" >&2; exit 1; }
    sudo="sudo"
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

configure() {  # configure <dir> [cmake args...]
  local dir="$1"; shift
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "$@" >/dev/null
}

build() {
  log "build: $BUILD (Release, $JOBS jobs)"
  configure "$BUILD" -DCMAKE_INSTALL_PREFIX="$BUILD/install"
  cmake --build "$BUILD" -j "$JOBS"
}

main_job() {
  deps
  build
  local map="$BUILD/basket_barrett.h5"
  # The map's arguments live in tools/readme_map.args (the tests that check this map read them).
  local args
  read -r -a args < "$ROOT/tools/readme_map.args"
  log "main: building the paper's task map (basket, three-finger hand, grasps that hold: ${args[*]})"
  (cd "$ROOT" && "$BUILD/bin/taskmap" build "${args[@]}" -o "$map")
  log "main: the map"
  "$BUILD/bin/taskmap" inspect "$map" --png "$BUILD/basket_barrett.png"
  echo "picture: $BUILD/basket_barrett.png"
}

consumer() {
  log "install + consumer: find_package(TaskMap) from the install tree"
  rm -rf "$BUILD/install"
  cmake --install "$BUILD" --prefix "$BUILD/install" >/dev/null
  for c in tests/consumer integration/examples; do
    [ -f "$ROOT/$c/CMakeLists.txt" ] || continue
    local d="$BUILD/consumer-$(basename "$c")"
    rm -rf "$d"
    cmake -S "$ROOT/$c" -B "$d" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTASKMAP_SOURCE_ROOT="$ROOT" \
      -DCMAKE_PREFIX_PATH="$BUILD/install" >/dev/null
    cmake --build "$d" -j "$JOBS" >/dev/null
    ctest --test-dir "$d" --output-on-failure
  done
}

test_all() {
  deps
  build
  log "tests: release build (unit, python, regression)"
  ctest --test-dir "$BUILD" -j "$JOBS" --output-on-failure --timeout 900
  consumer
  log "tests: sanitizer build (address,undefined), unit tests"
  configure "$ASAN_BUILD" -DTASKMAP_SANITIZE=address,undefined -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTASKMAP_BUILD_BENCHMARKS=OFF -DTASKMAP_BUILD_PYTHON=OFF -DTASKMAP_BUILD_TOOLS=OFF
  cmake --build "$ASAN_BUILD" -j "$JOBS"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    LSAN_OPTIONS=suppressions="$ROOT/tests/lsan.supp" \
    ctest --test-dir "$ASAN_BUILD" -L unit -j "$JOBS" --output-on-failure --timeout 1800
}

docs() {  # the generated reference (docs/REFERENCE.md), every warning an error
  deps
  build
  log "docs: the generated reference (command line, Python, C++)"
  /usr/bin/python3 "$ROOT/tools/docs/reference.py" --build "$BUILD"
}

bench() {
  deps
  build
  for b in "$BUILD"/tests/bench/*/*_bench; do
    [ -x "$b" ] || continue
    log "bench: $(basename "$b")"
    "$b" --benchmark_counters_tabular=true
  done
}

case "${1:-}" in
  main) main_job ;;
  test) test_all ;;
  deps) deps ;;
  build) deps; build ;;
  docs) docs ;;
  bench) bench ;;
  *) echo "usage: tools/dev.sh main|test|deps|build|docs|bench" >&2; exit 2 ;;
esac
