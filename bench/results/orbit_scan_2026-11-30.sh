#!/usr/bin/env bash
# Saddle orbits across pendulums (2026-11-30): which ones `eval period` finds at double.
#   bash bench/results/orbit_scan_2026-11-30.sh build/release/flipflux > bench/results/orbit_scan_2026-11-30.txt
# 1. point-mass pendulums (g = 9.81), both arms, 30 % and 80 % of the way from E_s to E_max;
# 2. the heavy-lower-link geometry of the cross-check's pendulum E (rigid first link, a1 = 0.25,
#    I1 = 0.0625, L2 = 2) with m2 from 64 to 2^20 and g scaled so that E_s = 4096, arm 2 at 30 %;
# 3. pendulum E's saddles (`flipflux model`): centre frequency and growth rate;
# 4. pendulum E's arm 1 next to its saddle, bounded by `timeout 60`.
set -u
FF=$1
echo "# bash bench/results/orbit_scan_2026-11-30.sh $FF ($($FF --version 2>&1 | head -1); $(date -u +%Y-%m-%dT%H:%MZ))"
first() { grep -E '"value"|"error_estimate"|error' | head -2 | tr -d '\n' | sed 's/  */ /g' | cut -c1-700; }
echo "## 1. point masses"
for P in "1 10 1 1" "1 5 0.5 2" "1 64 1 1" "1 2 0.5 2" "1 20 0.5 2" "2 1 1 0.5" "1 1 1 3"; do
  set -- $P
  for arm in 1 2; do for frac in 0.3 0.8; do
    E=$(python3 -c "m1,m2,L1,L2,g=$1,$2,$3,$4,9.81
a=g*(m1+m2)*L1; b=g*m2*L2; Es=2*b if $arm==2 else 2*a; print(round(Es+$frac*(2*a+2*b-Es),6))")
    echo "m1=$1 m2=$2 L1=$3 L2=$4 g=9.81 arm $arm frac $frac E $E: $(timeout 120 $FF eval period --arm $arm --m1 $1 --m2 $2 --L1 $3 --L2 $4 --g 9.81 --energy $E 2>&1 | first)"
  done; done
done
echo "## 2. heavy lower link"
for m2 in 64 1024 16384 262144 1048576; do
  g=$(python3 -c "print(repr(1/1024*(1048576/$m2)))")
  E=$(python3 -c "m2=$m2; g=$g; a=g*(0.25+m2*0.5); b=g*m2*2; print(repr(2*b+0.3*2*a))")
  echo "m2=$m2 g=$g arm 2 E $E: $(timeout 120 $FF eval period --arm 2 --m1 1 --m2 $m2 --L1 0.5 --a1 0.25 --I1 0.0625 --L2 2 --g $g --energy $E 2>&1 | first)"
done
echo "## 3. pendulum E's saddles"
$FF model --m1 1 --m2 1048576 --L1 0.5 --a1 0.25 --I1 0.0625 --L2 2 --g 0.0009765625 2>&1 \
  | grep -E '"energy"|"type"|"frequency"|"rate"' | tr -d '\n' | sed 's/  */ /g'; echo
echo "## 4. pendulum E, arm 1 (E_s = 1024.0005)"
for E in 1030; do
  s=$(date +%s); out=$(timeout 60 $FF eval period --arm 1 --m1 1 --m2 1048576 --L1 0.5 --a1 0.25 --I1 0.0625 --L2 2 --g 0.0009765625 --energy $E 2>&1 | first); rc=$?
  echo "arm 1 E $E: after $(( $(date +%s) - s )) s: ${out:-no result (timeout 60)}"
done
