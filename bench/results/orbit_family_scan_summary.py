# Summary of orbit_family_scan.py outputs: families scanned, families with a jump (an orbit of
# another family between two neighbouring energies), families not solved at all 40 energies, and
# the energies solved, and the unsolved energies by error where the files count them.
#   python3 bench/results/orbit_family_scan_summary.py LABEL FILE... >> bench/results/orbit_family_scan_summary.txt
import re, sys
label, files = sys.argv[1], sys.argv[2:]
families = jumps = unsolved = steps = solved = energies = 0
kinds = {}  # unsolved energies by error (files since the fifteenth session)
for f in files:
    for line in open(f):
        m = re.search(r'arm [12]: ([0-9]+)/([0-9]+) solved; ([0-9]+) jumps', line)
        if not m:
            continue
        families += 1
        jumps += int(m.group(3)) > 0
        unsolved += m.group(1) != m.group(2)
        steps += int(m.group(3))
        solved += int(m.group(1))
        energies += int(m.group(2))
        for c, k in re.findall(r"; ([0-9]+) ([a-z' ]+)", line):
            if k != "jumps":
                kinds[k] = kinds.get(k, 0) + int(c)
print(f"{label}: {families} families, {jumps} with a jump ({steps} jumps), {unsolved} not solved at every energy"
      f" ({solved} of {energies} energies solved)"
      + "".join(f"; {c} {k}" for k, c in sorted(kinds.items())))
