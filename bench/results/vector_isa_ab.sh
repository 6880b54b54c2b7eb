#!/usr/bin/env bash
# interleaved A/B of FLIPFLUX_VECTOR_ISA=avx2 vs avx512 on one binary; user CPU seconds; median of N
FF=$1; N=${2:-7}
export FLIPFLUX_PLUGIN_DIR=${FLIPFLUX_PLUGIN_DIR}
declare -A W
W[dop853_nochaos]="simulate --energy 5 --arm 2 --criteria upright,approx,saddle --trajectories 512 --time 100 --threads 1 --no-chaos --seed 1 --rtol 1e-10 --method dop853"
W[dop853_chaos]="simulate --energy 5 --arm 2 --criteria upright,approx,saddle --trajectories 512 --time 100 --threads 1 --seed 1 --rtol 1e-10 --method dop853"
W[taylor_L1]="simulate --energy 4.3 --arm 2 --criteria upright --trajectories 64 --time 2000 --threads 1 --no-chaos --seed 1 --rtol 3e-11"
W[taylor_L3]="simulate --energy 4.3 --arm 2 --criteria upright --trajectories 64 --time 2000 --threads 1 --no-chaos --seed 1 --rtol 3e-14"
for w in dop853_nochaos dop853_chaos taylor_L1 taylor_L3; do
  a=(); b=()
  for i in $(seq $N); do
    for isa in avx2 avx512; do
      t=$( { /usr/bin/time -f '%U' env FLIPFLUX_VECTOR_ISA=$isa taskset -c 0 $FF ${W[$w]} > ${TMPDIR:-/tmp}/out_$isa.json; } 2>&1 | tail -1)
      if [ $isa = avx2 ]; then a+=($t); else b+=($t); fi
    done
    cmp -s <(grep -v "seconds\|wall" ${TMPDIR:-/tmp}/out_avx2.json) <(grep -v "seconds\|wall" ${TMPDIR:-/tmp}/out_avx512.json) || echo "  outputs differ ($w)"
  done
  ma=$(printf '%s\n' "${a[@]}" | sort -g | awk '{x[NR]=$1} END{print x[int((NR+1)/2)]}')
  mb=$(printf '%s\n' "${b[@]}" | sort -g | awk '{x[NR]=$1} END{print x[int((NR+1)/2)]}')
  echo "$w: avx2 median user $ma s [${a[*]}]; avx512 median user $mb s [${b[*]}]; avx512/avx2 $(echo "$mb / $ma" | bc -l | cut -c1-5)"
done
