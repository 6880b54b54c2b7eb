#!/usr/bin/env bash
# Bounded libFuzzer runs of every fuzz target (fuzz/), seeded from the bundled files.
#   bash tools/fuzz.sh [SECONDS_PER_TARGET]   (default 8: about half a minute for the eight
#   targets, two at a time)
# Builds the "fuzz" preset (clang-14, ASan+UBSan, -O1) first, or the preset named by
# FLIPFLUX_FUZZ_PRESET (CI: "fuzz-ci", the same at -O0, which compiles in half the time). A crash
# leaves crash-* in build/PRESET/findings/TARGET/ and makes the script fail; each becomes a
# regression test.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-8}
preset=${FLIPFLUX_FUZZ_PRESET:-fuzz}
build=build/$preset
cmake --preset "$preset" >/dev/null
targets=(scene energy_grid decimal checkpoint orbit_cache candidate golden options)
cmake --build "$build" -j"${FLIPFLUX_FUZZ_JOBS:-2}" --target "${targets[@]/#/fuzz_}"
seeds=$build/seeds
rm -rf "$seeds" && mkdir -p "$seeds"
for t in "${targets[@]}"; do
    mkdir -p "$seeds/$t" "$build/findings/$t"
    rm -f "$build/findings/$t.report" "$build/findings/$t.status"
done
cp data/scenes/*.toml "$seeds/scene/"
printf '3' >"$seeds/energy_grid/1"; printf '2.5,3,3.5' >"$seeds/energy_grid/2"
printf '2:6:0.05' >"$seeds/energy_grid/3"
printf -- '--threads\x002\x00--interval\x001e-3' >"$seeds/options/1"
printf -- '--seed\x000x10\x00--list\x001,2.5,1e-400' >"$seeds/options/2"
printf '1.5\n1.50000001' >"$seeds/decimal/1"; printf -- '-2.5e-300\n0' >"$seeds/decimal/2"
printf '3.14159265358979323846264338327950288419716939937510' >"$seeds/decimal/3"
cp data/golden/*.csv "$seeds/golden/"
head -5 data/golden/golden.csv >"$seeds/candidate/1"
# fuzz/seeds/: a checkpoint of a finished two-energy run and saddle-orbit cache records (double,
# both arms), as flipflux wrote them; candidates with '# pendulum:' headers.
for t in "${targets[@]}"; do
    if [ -d "fuzz/seeds/$t" ]; then cp fuzz/seeds/"$t"/* "$seeds/$t/"; fi
done
# UBSan reports end the run (a crash), as ASan errors do.
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}
fuzz_one() {  # fuzz_one TARGET: its report line on stdout, or the failure on stderr (status 1)
    local t=$1 dir=$build/findings/$1
    rm -rf "$dir/tmp" && mkdir -p "$dir/tmp"
    # TMPDIR: the candidate and golden targets write their files there (removed below).
    if (cd "$dir" && TMPDIR=$PWD/tmp ../../fuzz/fuzz_"$t" -max_total_time="$seconds" -timeout=10 \
        -rss_limit_mb=2048 -print_final_stats=1 "../../seeds/$t" >log 2>&1); then
        echo "fuzz_$t: ${seconds}s, $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$dir/log" |
            grep -o '[0-9]*$') inputs, no crash"
    else
        echo "fuzz_$t: FAILED (input and report in $dir/):" >&2
        grep -A30 -m1 -E '^==[0-9]+==ERROR|runtime error|deadly signal|Timeout|out-of-memory' \
            "$dir/log" | head -40 >&2
        rm -rf "$dir/tmp"
        return 1
    fi
    rm -rf "$dir/tmp"
}
# One libFuzzer process per core (each is single-threaded): FLIPFLUX_FUZZ_JOBS at a time, their
# reports printed in the targets' order.
parallel=${FLIPFLUX_FUZZ_JOBS:-2}
running=0
for t in "${targets[@]}"; do
    if [ "$running" -ge "$parallel" ]; then wait -n || true; running=$((running - 1)); fi
    (
        s=0
        fuzz_one "$t" >"$build/findings/$t.report" 2>&1 || s=$?
        echo "$s" >"$build/findings/$t.status"
    ) &
    running=$((running + 1))
done
wait
status=0
for t in "${targets[@]}"; do
    cat "$build/findings/$t.report"
    [ "$(cat "$build/findings/$t.status" 2>/dev/null)" = 0 ] || status=1
done
exit $status
