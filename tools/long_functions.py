#!/usr/bin/env python3
"""Functions longer than a limit (default 120 lines) in src/ and include/: a function is a line
that opens a brace at column 0 or at one indentation level inside a class, to the matching brace
at the same indentation (the layout clang-format gives). Exit status 1 if any is found.

    python3 tools/long_functions.py [--limit 120]"""
import argparse
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
START = re.compile(r'^(?P<indent>(    )?)(?!namespace\b|struct\b|class\b|enum\b|union\b|extern\b|'
                   r'template\b|return\b|if\b|for\b|while\b|switch\b|else\b|do\b)[A-Za-z_~][^;]*\(')


def long_functions(limit):
    """(length, file, first line, text) of every function body longer than limit lines."""
    found = []
    for f in sorted(list(ROOT.glob("src/**/*.cpp")) + list(ROOT.glob("src/**/*.hpp")) +
                    list(ROOT.glob("include/**/*.hpp"))):
        lines = f.read_text(errors="replace").split("\n")
        i = 0
        while i < len(lines):
            m = START.match(lines[i])
            if not m or lines[i].rstrip().endswith(";"):
                i += 1
                continue
            # the signature runs to the first line ending in "{" (none: a declaration)
            k = i
            while k < len(lines) and k < i + 8 and not lines[k].rstrip().endswith(("{", ";")):
                k += 1
            if k >= len(lines) or not lines[k].rstrip().endswith("{") or "=" in lines[i].split("(")[0]:
                i += 1
                continue
            close = m.group("indent") + "}"
            j = k + 1
            while j < len(lines) and not (lines[j].startswith(close) and
                                          lines[j][len(close):len(close) + 1] in ("", ";", " ", ")")):
                j += 1
            length = j - i + 1
            if length > limit:
                found.append((length, f.relative_to(ROOT), i + 1, lines[i].strip()[:80]))
            i = j + 1
    return found


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--limit", type=int, default=120)
    args = ap.parse_args()
    found = long_functions(args.limit)
    for length, f, line, text in sorted(found, reverse=True):
        print(f"{length:5d} lines  {f}:{line}  {text}")
    print(f"{len(found)} functions longer than {args.limit} lines", file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
