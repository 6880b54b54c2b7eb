#!/usr/bin/env bash
# flipflux setup: installs what a fresh Debian 12 machine lacks, builds, and runs.
#
#   bash setup.sh main    install what the command-line tool needs (MAIN_PACKAGES only), build it
#                         (release, without tests, benchmarks or the Python module), run the
#                         default scene
#   bash setup.sh test    install, format check, one instrumented build (ASan+UBSan and coverage at
#                         -O0) running every test, coverage gate (lines of src/ and include/ >= 90 %)
#   bash setup.sh verify  install, release build, the verification suite with the checks too slow
#                         for CI (high precisions) and the unit tests (GCC -O2; CI's build is
#                         clang's), the libFuzzer targets built (clang-14) and run 8 s each
#                         (tools/fuzz.sh); writes docs/verification.md
#   bash setup.sh deps    install everything (idempotent: apt-get runs only when a package is
#                         missing); test and verify install everything too
set -euo pipefail
cd "$(dirname "$0")"

COVERAGE_GATE=90
JOBS=${JOBS:-$(nproc)}
# the command-line tool and the default scene
MAIN_PACKAGES=(
  g++ cmake ninja-build pkg-config git
  libboost-dev libmpfr-dev libgmp-dev libeigen3-dev libceres-dev libflint-arb-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev librandom123-dev
  libopenmpi-dev openmpi-bin
)
# tests, coverage, fuzzing, benchmarks, the Python module, the report, the viewer in a browser
EXTRA_PACKAGES=(
  clang-format libgtest-dev libbenchmark-dev lcov
  python3-matplotlib python3-mpmath python3-gmpy2 python3-scipy
  pybind11-dev python3-dev python3-numpy python3-pytest
  clang-14 libclang-rt-14-dev libomp-14-dev llvm-14
  chromium fonts-liberation
)
# verify's release build has the tests, benchmarks and Python module (main turns them off in
# build/release's cache; these turn them back on)
FULL=(-DFLIPFLUX_BUILD_TESTS=ON -DFLIPFLUX_BUILD_BENCHMARKS=ON -DFLIPFLUX_PYTHON=ON)

install_deps() {  # install_deps [main]: main's packages only, or everything
  local missing=() wanted=("${MAIN_PACKAGES[@]}")
  [ "${1:-}" = main ] || wanted+=("${EXTRA_PACKAGES[@]}")
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

build() {  # build PRESET [TARGET [CMAKE OPTIONS...]]: everything, or only TARGET and what it needs
  local preset=$1 target=${2:-}
  shift $(($# < 2 ? $# : 2))
  cmake --preset "$preset" "$@" >/dev/null
  cmake --build --preset "$preset" -j "$JOBS" ${target:+--target "$target"}
}

run_main() {
  build release flipflux_cli -DFLIPFLUX_BUILD_TESTS=OFF -DFLIPFLUX_BUILD_BENCHMARKS=OFF \
    -DFLIPFLUX_PYTHON=OFF
  # the default scene: predictions for every criterion and both arms, saddle-orbit families and an
  # exact-check ensemble; outputs in out/default/ (docs/scenes.md)
  ./build/release/flipflux run data/scenes/default.toml
}

run_ctest() {  # run_ctest PRESET DIR [ctest args]: full log to DIR, summary and failures here
  local preset=$1 dir=$2; shift 2
  local log=$dir/ctest-$preset.log
  if ctest --preset "$preset" -j "$JOBS" "$@" >"$log" 2>&1; then
    grep -E "tests passed|Total Test time" "$log"
  else
    grep -E "\*\*\*|Failed|tests passed" "$log" | head -50
    echo "ctest ($preset) FAILED; full log: $log" >&2
    ctest --preset "$preset" --rerun-failed --output-on-failure 2>&1 | tail -200
    return 1
  fi
}

format_check() {
  echo "== clang-format check"
  git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run --Werror
}

coverage_capture() {  # coverage_capture DIR: DIR/project.info, the lines of src/ and include/
  # Two lcov processes (one per core; lcov 1.16 is single-threaded and its capture was 4 of CI's
  # minutes): the library's objects, and the tests' (templates and inline functions of include/
  # they instantiate count too). Objects no test ran (a .gcno without a .gcda: a unit nothing
  # linked) count with zero hits (--initial, their folders only; the precompiled header is not
  # code).
  local dir=$1 pids=() status=0 part library=() tests=() gcov=()
  # a clang build's notes and counts are read by llvm-cov's gcov (gcc's gcov cannot)
  if grep -qs 'CMAKE_CXX_COMPILER_ID "Clang"' "$dir"/CMakeFiles/*/CMakeCXXCompiler.cmake; then
    gcov=(--gcov-tool "$PWD/tools/llvm_gcov.sh")
  fi
  for part in CMakeFiles python; do [ ! -d "$dir/$part" ] || library+=(--directory "$dir/$part"); done
  for part in tests verification; do [ ! -d "$dir/$part" ] || tests+=(--directory "$dir/$part"); done
  lcov --quiet --capture "${gcov[@]}" "${library[@]}" --output-file "$dir/run-library.info" \
    --rc lcov_branch_coverage=0 2>/dev/null &
  pids+=($!)
  lcov --quiet --capture "${gcov[@]}" "${tests[@]}" --output-file "$dir/run-tests.info" \
    --rc lcov_branch_coverage=0 2>/dev/null &
  pids+=($!)
  for p in "${pids[@]}"; do wait "$p" || status=1; done
  [ "$status" -eq 0 ] || { echo "lcov capture FAILED" >&2; return 1; }
  local parts=(-a "$dir/run-library.info" -a "$dir/run-tests.info")
  local unrun
  unrun=$(find "$dir" -name '*.gcno' ! -path '*flipflux_pch.dir*' | while read -r f; do
    [ -f "${f%.gcno}.gcda" ] || dirname "$f"; done | sort -u)
  if [ -n "$unrun" ]; then
    echo "coverage: objects no test ran (counted with zero hits): $(echo "$unrun" | wc -l) folders"
    local args=()
    for part in $unrun; do args+=(--directory "$part"); done
    lcov --quiet --capture --initial "${gcov[@]}" "${args[@]}" --output-file "$dir/unrun.info" \
      --rc lcov_branch_coverage=0 2>/dev/null
    parts+=(-a "$dir/unrun.info")
  fi
  lcov --quiet "${parts[@]}" -o "$dir/total.info" 2>/dev/null
  lcov --quiet --extract "$dir/total.info" "$PWD/src/*" "$PWD/include/*" \
    -o "$dir/project.info" 2>/dev/null
}

ci_tests() {
  echo "== instrumented build (ASan+UBSan, coverage, -O0) and every test"
  build ci
  local dir=build/ci
  find "$dir" -name '*.gcda' -delete
  run_ctest ci "$dir" --timeout 1800
  coverage_capture "$dir"
  genhtml --quiet "$dir/project.info" -o "$dir/html" >/dev/null 2>&1 || true
  echo "== coverage of src/ and include/ (HTML report: $dir/html/index.html)"
  local summary
  summary=$(lcov --summary "$dir/project.info" 2>&1 | grep -E "lines|functions")
  echo "$summary"
  local pct
  pct=$(echo "$summary" | sed -n 's/.*lines[^:]*: *\([0-9.]*\)%.*/\1/p')
  if awk -v p="$pct" -v g="$COVERAGE_GATE" 'BEGIN { exit !(p + 0 < g) }'; then
    echo "coverage gate FAILED: lines $pct% < $COVERAGE_GATE%"
    return 1
  fi
  echo "coverage gate passed: lines $pct% >= $COVERAGE_GATE%"
}

fuzz_check() {  # every reader of outside data under libFuzzer (fuzz/): a crash fails verify
  echo "== fuzz targets (clang-14, libFuzzer + ASan + UBSan), 8 s each"
  FLIPFLUX_FUZZ_JOBS=$JOBS FLIPFLUX_FUZZ_PRESET=fuzz-ci bash tools/fuzz.sh 8
}

run_verify() {
  echo "== release build and the verification suite (docs/verification.md)"
  build release "" "${FULL[@]}"
  local dir=build/release/verification-results
  rm -rf "$dir" && mkdir -p "$dir"
  local status=0
  run_ctest verify build/release --timeout 7200 \
    --output-junit "$PWD/$dir/ctest.xml" || status=1
  # the unit tests too, in GCC's optimised build: CI runs them in clang's instrumented one
  run_ctest release build/release -L unit --timeout 1800 \
    --output-junit "$PWD/$dir/unit.xml" || status=1
  fuzz_check || status=1
  python3 tools/verification_report.py --results "$dir" --out docs/verification.md
  return $status
}

# NOTE: each step is its own statement: `set -e` does not apply inside functions called as part
# of an && list, so chaining them would let a failed build go unnoticed.
case "${1:-}" in
  deps)
    install_deps ;;
  main)
    install_deps main
    run_main ;;
  test)
    install_deps
    format_check
    ci_tests ;;
  verify)
    install_deps
    run_verify ;;
  *)
    echo "usage: bash setup.sh main|test|verify|deps" >&2
    exit 2 ;;
esac
