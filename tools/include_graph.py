#!/usr/bin/env python3
"""The include graph of flipflux's modules, checked against the layers of docs/architecture
(../shared/STYLE.md): core <- model, special, quadrature, integrators, io <- prediction, orbits,
ensemble, certified, quantities <- study, output <- validation, report <- scene <- cli.

    python3 tools/include_graph.py            # print every module-to-module arrow, flag upward ones
    python3 tools/include_graph.py --check    # exit status 1 if any arrow points up or sideways
    python3 tools/include_graph.py --dot      # Graphviz on stdout

A module is the directory under include/flipflux/ or src/ (src/foo/x.cpp and include/flipflux/foo/
x.hpp are module foo); tests/ and verification/ are modules of their own that must not include
each other."""
import argparse
import collections
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent

# Lower layers first; a module may include its own layer's module only if listed as allowed below.
LAYERS = [
    ["core"],
    ["model", "special", "quadrature", "integrators", "io"],
    ["prediction", "orbits", "ensemble", "certified"],
    ["quantities"],
    ["study", "output"],
    ["validation", "report"],
    ["scene"],
    ["cli"],
]
# Same-layer arrows that are part of the design (a module above its sibling). certified -> orbits:
# a saddle-orbit proof takes the non-rigorous orbit as its centre (src/certified/
# saddle_orbit_proof.cpp); orbits never includes certified.
ALLOWED_SIDEWAYS = {("orbits", "prediction"), ("special", "quadrature"), ("io", "quadrature"),
                    ("certified", "orbits")}

LEVEL = {m: i for i, layer in enumerate(LAYERS) for m in layer}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)


def module_of(path: pathlib.Path):
    rel = path.relative_to(ROOT)
    parts = rel.parts
    if parts[0] == "include" and len(parts) > 3:
        return parts[2]
    if parts[0] == "src" and len(parts) > 2:
        return parts[1]
    if parts[0] in ("tests", "verification", "bench"):
        return parts[0]
    return None


def included_module(name: str, source: pathlib.Path):
    if name.startswith("flipflux/"):
        parts = name.split("/")
        return parts[1] if len(parts) > 2 else None
    # quoted relative include: resolve against the including file
    target = (source.parent / name).resolve()
    if target.exists() and ROOT in target.parents:
        return module_of(target)
    return None


def edges():
    found = collections.defaultdict(set)
    for pattern in ("include/**/*.hpp", "src/**/*.cpp", "src/**/*.hpp", "tests/**/*.cpp",
                    "tests/**/*.hpp", "verification/**/*.cpp", "verification/**/*.hpp",
                    "bench/**/*.cpp", "bench/**/*.hpp"):
        for f in ROOT.glob(pattern):
            src = module_of(f)
            if src is None:
                continue
            for name in INCLUDE.findall(f.read_text(errors="replace")):
                dst = included_module(name, f)
                if dst is not None and dst != src:
                    found[(src, dst)].add(str(f.relative_to(ROOT)))
    return found


def violation(src, dst):
    if {src, dst} == {"tests", "verification"}:
        return "tests and verification include each other"
    if src in LEVEL and dst in LEVEL:
        if LEVEL[dst] > LEVEL[src]:
            return "upward"
        if LEVEL[dst] == LEVEL[src] and (src, dst) not in ALLOWED_SIDEWAYS:
            return "sideways"
    if src in LEVEL and dst not in LEVEL:
        return "library includes " + dst
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--dot", action="store_true")
    args = ap.parse_args()
    found = edges()
    bad = 0
    if args.dot:
        print("digraph flipflux {\n  rankdir=BT;")
    for (src, dst), files in sorted(found.items()):
        why = violation(src, dst)
        bad += why is not None
        if args.dot:
            style = ' [color=red]' if why else ''
            print(f'  "{src}" -> "{dst}"{style};')
        elif why or not args.check:
            mark = f"  <-- {why}: {', '.join(sorted(files))}" if why else ""
            print(f"{src} -> {dst}{mark}")
    if args.dot:
        print("}")
    if not args.dot:
        print(f"{len(found)} arrows, {bad} against the layers", file=sys.stderr)
    return 1 if (args.check and bad) else 0


if __name__ == "__main__":
    sys.exit(main())
