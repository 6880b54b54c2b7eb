#!/usr/bin/env python3
"""Summarises bench_taylor_order's output (bench/taylor_order.cpp): for each accuracy level and
with or without the tangent vector, the automatic order's throughput against the best order of
the scan and against the order of Jorba & Zou's rule p = ceil(-ln(rtol) / 2) + 1 that the
ensemble used before (when the scan has it). Medians of the repetitions.

    taylor_order_summary.py BENCH_OUTPUT [--append]

--append adds the summary to the file, each line starting with "# summary".
"""
import argparse
import math
import re
import sys

LEVEL_RTOL = [3e-11, 2e-13, 3e-14, 2.220446049250313e-16]  # bench/taylor_order.cpp's level_rtol


def value(text):
    m = re.fullmatch(r"([0-9.]+)([kM]?)", text)
    if not m:
        raise ValueError(text)
    return float(m.group(1)) * {"": 1, "k": 1e3, "M": 1e6}[m.group(2)]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("output")
    p.add_argument("--append", action="store_true")
    a = p.parse_args()
    cells = {}
    with open(a.output) as f:
        for line in f:
            m = re.match(r"taylor_order_scan/(\d+)/(-?\d+)/(\d+)_median\s", line)
            if not m:
                continue
            counters = dict(re.findall(r"(\w+)=([0-9.]+[kM]?)", line))
            level, tangent = int(m.group(1)), int(m.group(3))
            order = int(value(counters["order"]))
            # an offset clamped to the highest order repeats a row: the first (offset 0) counts
            cells.setdefault((level, tangent), {}).setdefault(order, (
                value(counters["units_per_cpu_s"]), int(value(counters["automatic_order"]))))
    if not cells:
        sys.exit(f"taylor_order_summary.py: no median rows in {a.output}")
    lines = []
    for (level, tangent), by_order in sorted(cells.items()):
        automatic = next(iter(by_order.values()))[1]
        best = max(by_order, key=lambda o: by_order[o][0])
        auto_rate = by_order[automatic][0]
        old = math.ceil(-math.log(LEVEL_RTOL[level]) / 2) + 1
        old_text = (f"Jorba-Zou order {old} {by_order[old][0] / 1e3:.1f}k, automatic/Jorba-Zou "
                    f"{auto_rate / by_order[old][0]:.3f}" if old in by_order else
                    f"Jorba-Zou order {old} not scanned")
        lines.append(f"# summary L{level + 1} tangent {tangent}: automatic order {automatic} "
                     f"{auto_rate / 1e3:.1f}k units/CPU-s; best order {best} "
                     f"{by_order[best][0] / 1e3:.1f}k, automatic/best {auto_rate / by_order[best][0]:.3f}; "
                     f"{old_text}")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if a.append:
        with open(a.output, "a") as f:
            f.write(text)


if __name__ == "__main__":
    main()
