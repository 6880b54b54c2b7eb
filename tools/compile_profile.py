#!/usr/bin/env python3
"""The compile-time profile of a build tree from its .ninja_log: the slowest units, the total
CPU time and the number of units, as a Markdown table (docs/development.md).

    python3 tools/compile_profile.py build/release [--top 12]"""
import argparse
import pathlib
import sys


def profile(build_dir: pathlib.Path):
    """(seconds, output) of every step of the last build recorded in build_dir/.ninja_log."""
    log = build_dir / ".ninja_log"
    if not log.is_file():
        sys.exit(f"compile_profile: '{log}' does not exist (build first)")
    latest = {}
    for line in log.read_text().splitlines():
        if line.startswith("#"):
            continue
        fields = line.split("\t")
        if len(fields) != 5:
            sys.exit(f"compile_profile: '{log}': malformed line '{line}'")
        start, end, _, output, _ = fields
        latest[output] = (int(end) - int(start)) / 1000
    return sorted(((s, o) for o, s in latest.items()), reverse=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build_dir", type=pathlib.Path)
    ap.add_argument("--top", type=int, default=12)
    args = ap.parse_args()
    steps = profile(args.build_dir)
    units = [(s, o) for s, o in steps if o.endswith((".o", ".gch"))]
    print(f"{len(units)} compiled units, {sum(s for s, _ in units):.0f} CPU-seconds in total "
          f"(links and other steps: {sum(s for s, o in steps if (s, o) not in units):.0f} s)\n")
    print("| seconds | unit |\n|---:|---|")
    for s, o in units[:args.top]:
        print(f"| {s:.1f} | `{o.replace('.dir/', '/').replace('CMakeFiles/', '')}` |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
