#!/usr/bin/env python3
"""Numbers in the docs that a run produced, checked against the committed run data they quote.

    python3 tools/doc_numbers.py --check      # exit status 1 if a quoted number differs from its source
    python3 tools/doc_numbers.py --update     # rewrite every quoted number from its source
    python3 tools/doc_numbers.py --self-test  # a wrong number is caught, --update repairs it (temp dir)

A marker follows the number it sources, with nothing between them:

    Σz² = 36.8<!-- src: docs/reproduction/run/ensemble-arm2.json agreement.saddle.all_trajectories.chi2 .1f -->

    <!-- src: FILE KEY [OP ...] FORMAT -->

FILE   a path from the repository root: a .json file, a .csv file (read as a list of rows, each
       a mapping from column name to text), or any other text file (a generated .md).
KEY    for JSON and CSV a path into it: names separated by dots; [3] a list element by index;
       [field=value] the one list element whose field equals value (numerically when both parse
       as numbers: [energy=5] matches "5" and "5.0"), [f=a,g=b] both; a name with dots, spaces or
       brackets in double quotes ("q0.001", "IQI [%]"). For a text file, a regular expression
       whose first group is the number (its first match counts). A KEY (or OP) with spaces
       outside double quotes is written in single quotes as a whole.
OP     applied in order: *100, /60, +1, -1 (any number), or *@KEY, /@KEY, +@KEY, -@KEY (another
       value of the same JSON or CSV file); abs; len (the length of a list); for a text file,
       min or max as the first OP: over every match of the pattern, not the first.
FORMAT a Python format spec: .2f, .1f, d, ,d (thousands separators), .3g.

The number before the marker may use the typographic minus (−); it is kept on --update. Files
scanned: README.md and docs/*.md (not docs/reproduction*/: those are generated from the run itself).
"""
import argparse
import csv
import json
import os
import pathlib
import re
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent

# The number written right before a marker, and the marker's content.
NUMBER = r"(?P<number>[−-]?\d[\d,]*(?:\.\d+)?(?:[eE][−+-]?\d+)?)"
MARKER = re.compile(NUMBER + r"<!--\s*src:\s*(?P<spec>.*?)\s*-->")
# A marker not directly after a number is an error too (a stray space, a number deleted).
ANY_MARKER = re.compile(r"<!--\s*src:")
TOKEN = re.compile(r"""(?:'[^']*'|"[^"]*"|[^\s'"])+""")
SEGMENT = re.compile(r'"(?P<quoted>[^"]*)"|\[(?P<bracket>[^\]]*)\]|(?P<name>[^.\["]+)')


class SourceError(Exception):
    pass


def doc_files(root):
    return [root / "README.md"] + sorted((root / "docs").glob("*.md"))


def as_number(text):
    """A JSON or CSV value as int or float; None if it is not a number."""
    if isinstance(text, bool):
        return None
    if isinstance(text, (int, float)):
        return text
    try:
        return int(text)
    except (TypeError, ValueError):
        pass
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def key_segments(key):
    """'energies[energy=5].criteria.saddle.residence_times."q0.001"' -> [(kind, text), ...]."""
    segments, pos = [], 0
    while pos < len(key):
        if key[pos] == ".":
            pos += 1
            continue
        match = SEGMENT.match(key, pos)
        if not match:
            raise SourceError(f"bad key {key!r} at {key[pos:]!r}")
        if match.group("quoted") is not None:
            segments.append(("name", match.group("quoted")))
        elif match.group("bracket") is not None:
            segments.append(("select", match.group("bracket")))
        else:
            segments.append(("name", match.group("name")))
        pos = match.end()
    return segments


def same_value(value, wanted):
    a, b = as_number(value), as_number(wanted)
    if a is not None and b is not None:
        return a == b
    return str(value) == wanted


def lookup(data, key):
    for kind, text in key_segments(key):
        if kind == "name":
            if not isinstance(data, dict) or text not in data:
                raise SourceError(f"no key {text!r}")
            data = data[text]
        elif re.fullmatch(r"-?\d+", text):
            if not isinstance(data, list) or not -len(data) <= int(text) < len(data):
                raise SourceError(f"no element [{text}]")
            data = data[int(text)]
        else:
            conditions = [c.partition("=") for c in text.split(",")]
            if not isinstance(data, list) or any(not sep for _, sep, _ in conditions):
                raise SourceError(f"bad selector [{text}]")
            found = [e for e in data if isinstance(e, dict)
                     and all(f in e and same_value(e[f], wanted) for f, _, wanted in conditions)]
            if len(found) != 1:
                raise SourceError(f"[{text}] selects {len(found)} elements, not one")
            data = found[0]
    return data


def read_source(root, path, cache):
    if path not in cache:
        full = root / path
        try:
            with open(full, encoding="utf-8", newline="") as f:
                if path.endswith(".json"):
                    cache[path] = json.load(f)
                elif path.endswith(".csv"):
                    cache[path] = list(csv.DictReader(f))
                else:
                    cache[path] = f.read()
        except (OSError, ValueError) as error:
            raise SourceError(f"cannot read {path}: {error}") from None
    return cache[path]


def apply(value, op, data):
    if op == "len":
        if not isinstance(value, list):
            raise SourceError("len of a non-list")
        return len(value)
    number = as_number(value)
    if number is None:
        raise SourceError(f"not a number: {value!r}")
    if op == "abs":
        return abs(number)
    if op[:1] in ("*", "/", "+", "-") and len(op) > 1:
        operand = as_number(lookup(data, op[2:]) if op[1] == "@" else op[1:])
        if operand is None:
            raise SourceError(f"bad operand in {op!r}")
        return {"*": number * operand, "/": number / operand if operand else float("nan"),
                "+": number + operand, "-": number - operand}[op[0]]
    raise SourceError(f"unknown operation {op!r}")


def source_text(root, spec, cache):
    """The marker's source value, formatted as the doc should write it."""
    tokens = [t[1:-1] if t.startswith("'") else t for t in TOKEN.findall(spec)]
    if len(tokens) < 3:
        raise SourceError("a marker needs FILE KEY [OP ...] FORMAT")
    path, key, *ops, spec_format = tokens
    data = read_source(root, path, cache)
    if isinstance(data, str) and ops[:1] in (["min"], ["max"]):
        # min / max first: over every match of the pattern
        try:
            found = [m.group(1).replace("−", "-") for m in re.finditer(key, data)
                     if m.groups() and m.group(1) is not None]
        except re.error as error:
            raise SourceError(f"bad pattern {key!r}: {error}") from None
        numbers = [as_number(v) for v in found]
        if not numbers or None in numbers:
            raise SourceError(f"no numeric match of {key!r}")
        value = (min if ops[0] == "min" else max)(numbers)
        ops = ops[1:]
    elif isinstance(data, str):
        try:
            match = re.search(key, data)
        except re.error as error:
            raise SourceError(f"bad pattern {key!r}: {error}") from None
        if not match or not match.groups():
            raise SourceError(f"no match of {key!r}")
        value = match.group(1).replace("−", "-")
    else:
        value = lookup(data, key)
    for op in ops:
        value = apply(value, op, data)
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        number = as_number(value)
        if number is None:
            raise SourceError(f"not a number: {value!r}")
        value = number
    if spec_format.endswith("d") and isinstance(value, float):
        if not value.is_integer():
            raise SourceError(f"format {spec_format} of a non-integer {value!r}")
        value = int(value)
    try:
        text = format(value, spec_format)
    except ValueError as error:
        raise SourceError(f"format {spec_format!r}: {error}") from None
    if re.fullmatch(r"-0(\.0*)?", text):  # -0.0 rounds to 0.0
        text = text[1:]
    return text


def process(root, path, update, cache):
    """(markers checked, problems) for one file; with update, rewrites it from the sources."""
    text = path.read_text(encoding="utf-8")
    problems, checked, pieces, last = [], 0, [], 0
    name = path.relative_to(root)
    sourced = set()
    for match in MARKER.finditer(text):
        line = text.count("\n", 0, match.start()) + 1
        sourced.add(match.start("spec"))
        written = match.group("number")
        checked += 1
        try:
            wanted = source_text(root, match.group("spec"), cache)
        except SourceError as error:
            problems.append(f"{name}:{line}: {written}: {error} ({match.group('spec')})")
            continue
        if "−" in written:
            wanted = wanted.replace("-", "−")
        if written == wanted:
            continue
        if update:
            pieces += [text[last:match.start("number")], wanted]
            last = match.end("number")
        else:
            problems.append(f"{name}:{line}: written {written}, source gives {wanted} ({match.group('spec')})")
    for match in ANY_MARKER.finditer(text):
        spec_start = text.find("src:", match.start()) + 4
        spec_start += len(text[spec_start:]) - len(text[spec_start:].lstrip())
        if spec_start not in sourced:
            line = text.count("\n", 0, match.start()) + 1
            problems.append(f"{name}:{line}: marker not directly after a number")
    if update and pieces:
        pieces.append(text[last:])
        write_atomically(path, "".join(pieces))
    return checked, problems


def write_atomically(path, text):
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as f:
            f.write(text)
        os.chmod(temporary, path.stat().st_mode & 0o777)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def run(root, files, update):
    cache, checked, problems = {}, 0, []
    for path in files:
        n, p = process(root, path, update, cache)
        checked, problems = checked + n, problems + p
    return checked, problems


def self_test():
    """A deliberately wrong number is reported, --update repairs it, a bad source is an error."""
    failures = []
    with tempfile.TemporaryDirectory() as directory:
        root = pathlib.Path(directory)
        (root / "docs").mkdir()
        (root / "run.json").write_text(json.dumps({
            "seconds": 576.253,
            "energies": [{"energy": "5", "criteria": {"saddle": {"count": 146583, "q": {"q0.001": "1.9342"}}}},
                         {"energy": "5.3", "criteria": {"saddle": {"z_score": "-0.37"}}}],
            "agreement": {"saddle": {"chi2": "36.785945368724448"}}}), encoding="utf-8")
        (root / "t.csv").write_text('regime,energies,IQI [%]\n"full (2 < E < 6)",39,0.42\nlow,3,0.5\nlow,7,0.77\n', encoding="utf-8")
        doc = root / "docs" / "a.md"
        doc.write_text(
            "Σz² = 34.1<!-- src: run.json agreement.saddle.chi2 .1f --> over 39 energies;\n"
            "run time ≈ 57<!-- src: run.json seconds /60 .0f --> min;\n"
            "1,490,579<!-- src: run.json energies[energy=5.0].criteria.saddle.count ,d --> times,\n"
            'quantile 1.934<!-- src: run.json energies[energy=5].criteria.saddle.q."q0.001" .3f -->,\n'
            "z = −0.37<!-- src: run.json energies[1].criteria.saddle.z_score .2f -->,\n"
            "IQI 0.42<!-- src: t.csv '[regime=full (2 < E < 6)].\"IQI [%]\"' .2f --> %,\n"
            "2<!-- src: run.json energies len d --> energies,\n"
            "IQI 0.77<!-- src: t.csv [regime=low,energies=7].\"IQI [%]\" .2f --> %,\n"
            "−1.01<!-- src: run.json energies[1].criteria.saddle.z_score /@agreement.saddle.chi2 *100 .2f --> %,\n"
            "took 96.8<!-- src: docs/r.md 'took \\*\\*([0-9.]+) s' .1f --> s,\n"
            "between 1.5<!-- src: docs/r.md 'x=([0-9.]+)' min .1f --> and 9.5<!-- src: docs/r.md 'x=([0-9.]+)' max *10 .1f -->.\n",
            encoding="utf-8")
        (root / "docs" / "r.md").write_text("the run took **96.8 s** of wall time\nx=3.5 x=0.95 x=1.5\n",
                                            encoding="utf-8")
        (root / "README.md").write_text("no markers\n", encoding="utf-8")
        checked, problems = run(root, doc_files(root), update=False)
        expected = ["docs/a.md:1: written 34.1, source gives 36.8", "docs/a.md:2: written 57, source gives 10",
                    "docs/a.md:3: written 1,490,579, source gives 146,583",
                    "docs/a.md:11: written 1.5, source gives 0.9", "docs/a.md:11: written 9.5, source gives 35.0"]
        if checked != 12 or [p.split(" (")[0] for p in problems] != expected:
            failures.append(f"check: {checked} checked, problems {problems}")
        run(root, doc_files(root), update=True)
        checked, problems = run(root, doc_files(root), update=False)
        if checked != 12 or problems or "36.8<!--" not in doc.read_text(encoding="utf-8"):
            failures.append(f"after --update: {checked} checked, problems {problems}")
        if "−0.37<!--" not in doc.read_text(encoding="utf-8"):
            failures.append("--update lost the typographic minus")
        for bad, why in [("1<!-- src: missing.json seconds .0f -->", "cannot read"),
                         ("1<!-- src: run.json energies[energy=6].x .0f -->", "selects 0 elements"),
                         ("1<!-- src: run.json seconds %.1f -->", "format"),
                         ("x <!-- src: run.json seconds .0f -->", "not directly after a number")]:
            doc.write_text(bad + "\n", encoding="utf-8")
            _, problems = run(root, doc_files(root), update=False)
            if len(problems) != 1 or why not in problems[0]:
                failures.append(f"{bad!r}: expected one problem with {why!r}, got {problems}")
    for failure in failures:
        print("FAIL", failure)
    print(f"doc_numbers self-test: {'failed' if failures else 'passed'}")
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true", help="report every quoted number that differs from its source")
    mode.add_argument("--update", action="store_true", help="rewrite the quoted numbers from their sources")
    mode.add_argument("--self-test", action="store_true", help="check this tool on temporary files")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    checked, problems = run(ROOT, doc_files(ROOT), update=args.update)
    for problem in problems:
        print(problem)
    verb = "updated from their sources" if args.update else "checked"
    print(f"doc numbers: {checked} {verb}, {len(problems)} {'unreadable' if args.update else 'differ'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
