#!/usr/bin/env bash
# The README's two set-up commands, for a fresh Debian 12 machine as root (or with sudo):
#   bash scripts/setup.sh demo   installs what is missing, builds, converts the generated samples
#   bash scripts/setup.sh test   installs what is missing, builds (plain and ASan+UBSan), runs every test
set -euo pipefail
mode=${1:-}
case "$mode" in demo|test) ;; *) echo "usage: bash scripts/setup.sh demo|test" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."
jobs=$(nproc)

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
packages=(g++ cmake ninja-build pkg-config libtinygltf-dev nlohmann-json3-dev libdraco-dev libopenimageio-dev
          libspng-dev libdeflate-dev libturbojpeg0-dev libmeshoptimizer-dev libxxhash-dev libglm-dev libcli11-dev libgtest-dev libyaml-cpp-dev libcgal-dev
          libbenchmark-dev python3-dev python3-pybind11)
# The Python module's tests run under Debian's pytest; the Dask driver's (dist/) on a local cluster.
if [ "$mode" = test ]; then packages+=(python3-pytest python3-distributed); fi
# The meshopt asset test (tests/meshopt) compares preview images with Pillow, and the convert
# fuzzer's seeds (scripts/fuzz_seeds.py) are made with it.
if [ "$mode" = test ]; then packages+=(python3-pil); fi
# The gallery page's test opens it in Debian's headless chromium (tests/preview/browser.py).
if [ "$mode" = test ]; then packages+=(chromium); fi
# The tests check converted files with the Khronos validator from npm; keep an existing node.
if [ "$mode" = test ] && ! command -v npm >/dev/null; then packages+=(nodejs npm); fi
# The sanitizer build and the fuzzer need clang and its runtimes. LeakSanitizer's suppressions of
# the dynamic loader's own allocations (tests/lsan.supp) match by symbol, and ld.so has symbols
# only with libc6-dbg: without it every test that dlopens a module reports a leak inside ld-linux.
if [ "$mode" = test ]; then packages+=(clang libclang-rt-14-dev libc6-dbg); fi
# cpack -G DEB (the package test, and the README's recipe) finds binaries with file(1) and their
# dependencies with dpkg-shlibdeps; without them it fails or writes a package with no Depends.
packages+=(file dpkg-dev)
missing=()
for p in "${packages[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p"); done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

build() {  # build DIR [cmake options...]
  local dir=$1
  shift
  cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
}

if [ "$mode" = demo ]; then
  build build -DCMAKE_BUILD_TYPE=Release -DGLTF_PBR_TESTS=OFF
  ./build/gltf-pbr convert build/samples -o out --report out/samples-report.json -v
  echo "converted samples in out/samples, report in out/samples-report.json" >&2
else
  # Every phase runs, whatever an earlier one did; the summary names the ones that failed.
  failed=()
  phase() {  # phase NAME COMMAND...
    local name=$1
    shift
    echo "== $name" >&2
    "$@" || failed+=("$name")
  }
  # Each ctest run also writes JUnit XML, so the summary can show a failed test's own output after
  # the later phases' output has pushed ctest's list out of sight.
  run_tests() {  # run_tests DIR
    ctest --test-dir "$1" --output-on-failure -j "$jobs" --output-junit "$PWD/$1/tests.xml"
  }
  plain_tests() {
    rm -f build/tests.xml  # a build that fails leaves no earlier run's failures to report
    build build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLTF_PBR_TESTS=ON && run_tests build
  }
  # The same tests under AddressSanitizer + UndefinedBehaviorSanitizer, built by clang (installed
  # for the fuzzer anyway): it compiles this tree instrumented in about half of GCC 12's time, and
  # its instrumented code runs faster (bench/RESULTS.md, "CI time").
  sanitizer_tests() {
    rm -f build-sanitize/tests.xml
    build build-sanitize -DCMAKE_BUILD_TYPE=Debug -DGLTF_PBR_SANITIZE=ON -DGLTF_PBR_TESTS=ON \
      -DCMAKE_CXX_COMPILER=clang++ &&
      ASAN_OPTIONS=detect_leaks=1 run_tests build-sanitize
  }
  # For the summary: each failed test of a ctest run, with the last lines of its output.
  failed_tests() {  # failed_tests DIR
    [ -f "$1/tests.xml" ] || return 0
    python3 - "$1/tests.xml" <<'PYTHON' >&2 || true
import sys, xml.etree.ElementTree as ElementTree
for case in ElementTree.parse(sys.argv[1]).getroot().iter("testcase"):
    if case.get("status") == "fail" or case.find("failure") is not None:
        output = (case.findtext("system-out") or "").rstrip().splitlines()
        print(f"-- {case.get('name')}: failed; the last lines of its output:")
        print("\n".join("   " + line for line in output[-25:]))
PYTHON
  }
  # Load + validate, and convert with its preview, under libFuzzer for a bounded time each
  # (scripts/fuzz.sh has the seeds).
  fuzzing() {
    cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
      -DGLTF_PBR_FUZZ=ON -DGLTF_PBR_TESTS=OFF >/dev/null &&
      cmake --build build-fuzz -j "$jobs" --target fuzz-validate fuzz-convert || return 1
    local status=0  # both run, whatever the first finds
    bash scripts/fuzz.sh build-fuzz/fuzz/fuzz-validate "${GLTF_PBR_FUZZ_SECONDS:-120}" || status=1
    bash scripts/fuzz.sh build-fuzz/fuzz/fuzz-convert "${GLTF_PBR_FUZZ_SECONDS:-120}" || status=1
    return "$status"
  }
  phase "plain tests" plain_tests
  phase "sanitizer tests" sanitizer_tests
  phase "fuzzing" fuzzing
  if [ "${#failed[@]}" -gt 0 ]; then
    for name in "${failed[@]}"; do
      case "$name" in
        "plain tests") failed_tests build ;;
        "sanitizer tests") failed_tests build-sanitize ;;
      esac
    done
    printf 'FAILED phases: %s\n' "$(IFS=,; echo "${failed[*]}")" >&2
    exit 1
  fi
  echo "all phases passed: plain tests, sanitizer tests, fuzzing" >&2
fi
