#!/usr/bin/env bash
# flipflux setup: installs what a fresh Debian 12 machine lacks, builds, and runs.
#
#   bash setup.sh main   install, build (release), run the default scene
#   bash setup.sh test   install, format check, ASan+UBSan unit tests, coverage build running every
#                        test, coverage gate (lines of src/ and include/ >= 90 %)
#   bash setup.sh deps   install only (idempotent: apt-get runs only when a package is missing)
set -euo pipefail
cd "$(dirname "$0")"

COVERAGE_GATE=90
JOBS=${JOBS:-$(nproc)}
PACKAGES=(
  g++ cmake ninja-build pkg-config git clang-format
  libboost-dev libmpfr-dev libgmp-dev libeigen3-dev libceres-dev
  libgtest-dev libbenchmark-dev lcov
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev librandom123-dev
  libopenmpi-dev openmpi-bin python3-matplotlib python3-mpmath
)

install_deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
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

build() {  # build PRESET
  cmake --preset "$1" >/dev/null
  cmake --build --preset "$1" -j "$JOBS"
}

run_main() {
  build release
  # the default scene: predictions for every criterion and both arms, saddle-orbit families and an
  # exact-check ensemble; outputs in out/default/ (docs/scenes.md)
  ./build/release/flipflux run data/scenes/default.toml
}

run_ctest() {  # run_ctest PRESET [ctest args]: full log to the build tree, summary and failures here
  local preset=$1; shift
  local log=build/$preset/ctest.log
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

sanitizer_tests() {
  echo "== ASan+UBSan build and unit tests"
  build asan-ubsan
  run_ctest asan-ubsan --timeout 900
}

coverage_tests() {
  echo "== coverage build and every test"
  build coverage
  local dir=build/coverage
  find "$dir" -name '*.gcda' -delete
  lcov --quiet --capture --initial --directory "$dir" --output-file "$dir/base.info" \
    --rc lcov_branch_coverage=0 2>/dev/null
  run_ctest coverage --timeout 1800
  lcov --quiet --capture --directory "$dir" --output-file "$dir/run.info" \
    --rc lcov_branch_coverage=0 2>/dev/null
  lcov --quiet -a "$dir/base.info" -a "$dir/run.info" -o "$dir/total.info" 2>/dev/null
  lcov --quiet --extract "$dir/total.info" "$PWD/src/*" "$PWD/include/*" \
    -o "$dir/project.info" 2>/dev/null
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

# NOTE: each step is its own statement: `set -e` does not apply inside functions called as part
# of an && list, so chaining them would let a failed build go unnoticed.
case "${1:-}" in
  deps)
    install_deps ;;
  main)
    install_deps
    run_main ;;
  test)
    install_deps
    format_check
    sanitizer_tests
    coverage_tests ;;
  *)
    echo "usage: bash setup.sh main|test|deps" >&2
    exit 2 ;;
esac
