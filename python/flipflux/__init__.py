"""flipflux from Python: verified flip-rate predictions for the double pendulum.

The same library as the ``flipflux`` command-line tool, with the same values digit for digit::

    import flipflux
    v = flipflux.evaluate("omega", "3", precision="quad")
    v.value        # mpmath.mpf with every digit of quad (mpmath.mp.dps set from the precision)
    v.text         # the decimal string `flipflux eval omega --energy 3 --precision quad` prints

Numbers going in (energies, pendulum parameters) may be

* ``str``: an exact decimal, parsed in the working precision (``"0.1"`` is one tenth, rounded
  once to the working precision) -- the way to pass a value exactly;
* ``int``, ``decimal.Decimal``, ``fractions.Fraction`` with a terminating decimal expansion;
* ``float``: taken as its exact binary value (``0.1`` is 0.1000000000000000055511151231257827...,
  exactly what the float holds, not one tenth); ``mpmath.mpf`` likewise (its exact binary value).

Bad input raises ``ValueError`` with the command-line tool's one-line message (e.g.
``--energy: ...``). Long calls release the GIL and respond to Ctrl-C (``KeyboardInterrupt``):
``simulate`` stops its trajectories; ``evaluate`` and ``saddle_orbit`` return control at once and
let the abandoned computation finish in the background. See docs/python.md.
"""
import csv as _csv
import decimal as _decimal
import fractions as _fractions
import io as _io
import os as _os
from typing import NamedTuple as _NamedTuple

import mpmath as _mpmath
import numpy as _np

from . import _flipflux

__all__ = ["Pendulum", "Value", "evaluate", "saddle_orbit", "simulate", "validate", "quantities",
           "golden_dir", "__version__"]
__version__ = _flipflux.version()


def _text(x, name):
    """The exact decimal text of a number (see the module's docstring)."""
    if isinstance(x, bool):
        raise ValueError(f"{name}: '{x}' is not a number")
    if isinstance(x, str):
        return x.strip()
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if x != x or x in (float("inf"), float("-inf")):
            return repr(x)  # the library names it as not finite
        return format(_decimal.Decimal(x), "f")  # exact: a float is a dyadic rational
    if isinstance(x, _decimal.Decimal):
        return format(x, "f")
    if isinstance(x, _fractions.Fraction):
        d = _decimal.Decimal(x.numerator)
        den = x.denominator
        twos = fives = 0
        while den % 2 == 0:
            den //= 2
            twos += 1
        while den % 5 == 0:
            den //= 5
            fives += 1
        if den != 1:
            raise ValueError(f"{name}: {x} has no finite decimal expansion (pass a str)")
        k = max(twos, fives)
        scaled = x.numerator * 2 ** (k - twos) * 5 ** (k - fives)
        return format(_decimal.Decimal(scaled).scaleb(-k), "f")
    if isinstance(x, _mpmath.mpf):
        sign, man, exp, _ = x._mpf_
        if not man and exp:
            return str(x)  # nan, inf
        value = _fractions.Fraction(int(man)) * _fractions.Fraction(2) ** int(exp)
        return ("-" if sign else "") + _text(value, name)
    raise ValueError(f"{name}: {x!r} is not a number (str, int, float, Decimal or mpmath.mpf)")


class Pendulum:
    """A double pendulum of two rigid links (defaults: the paper's egalitarian pendulum, unit
    point masses on unit massless rods, g = 1).

    m1, m2: masses of the links (> 0); L1: pivot to joint; L2: length of link 2 (> 0);
    a1, a2: distances to the links' centres of mass (None: L1, L2, i.e. point masses);
    I1, I2: moments of inertia about the centres of mass (>= 0); g: gravity (> 0).
    Numbers as described in the module's docstring (str for exact decimals)."""

    def __init__(self, m1=1, m2=1, L1=1, L2=1, a1=None, a2=None, I1=0, I2=0, g=1):
        given = dict(m1=m1, m2=m2, L1=L1, L2=L2, a1=a1, a2=a2, I1=I1, I2=I2, g=g)
        self.parameters = {k: _text(v, k) for k, v in given.items() if v is not None}

    def __repr__(self):
        return "Pendulum(" + ", ".join(f"{k}={v!r}" for k, v in self.parameters.items()) + ")"


def _parameters(pendulum):
    if pendulum is None:
        return {}
    if not isinstance(pendulum, Pendulum):
        raise ValueError(f"pendulum: {pendulum!r} is not a flipflux.Pendulum")
    return dict(pendulum.parameters)


def _digits(precision_name):
    """Significant decimal digits of a precision as flipflux prints it."""
    if precision_name == "double":
        return 17
    if precision_name == "quad":
        return 36
    return int(precision_name.split(":")[1]) + 2


def _number(text, precision_name):
    """A float at double; else an mpmath.mpf from the full decimal string, with mpmath.mp.dps
    raised (never lowered) so that the string's digits are all kept."""
    if precision_name == "double":
        return float(text)
    _mpmath.mp.dps = max(_mpmath.mp.dps, _digits(precision_name) + 5)
    return _mpmath.mpf(text)


class Value(_NamedTuple):
    """evaluate()'s result: value and error estimate as float (double) or mpmath.mpf (quad, mp:N),
    the decimal strings the command-line tool prints, and the method used."""
    value: object
    error_estimate: object
    text: str
    error_text: str
    method: str
    precision: str
    seconds: float

    def __str__(self):
        return f"{self.text} +- {self.error_text} ({self.method}, {self.precision})"


def quantities():
    """Every quantity evaluate() knows: {name: (description, methods, per_arm)}."""
    return {n: (d, m, a) for n, d, m, a in _flipflux.quantities()}


def evaluate(quantity, energy, arm=2, precision="double", method=None, pendulum=None):
    """One quantity ("omega", "flux-upright", "rate-saddle", "period", ... see quantities()) at
    energy E for the given arm, in precision "double", "quad" or "mp:N" -- `flipflux eval`.
    Returns a Value (value and error estimate: float at double, mpmath.mpf otherwise)."""
    r = _flipflux.evaluate(quantity, _text(energy, "energy"), _text(arm, "arm"), precision,
                           method or "", _parameters(pendulum))
    return Value(_number(r["value"], r["precision"]), _number(r["error_estimate"], r["precision"]),
                 r["value"], r["error_estimate"], r["method"], r["precision"], r["seconds"])


def saddle_orbit(energy, arm=2, precision="double", samples=101, method="periodic",
                 pendulum=None):
    """The saddle orbit at energy E -- `flipflux orbit`. Returns a dict: "samples" (N rows t,
    theta1, theta2, l1, l2 at t = k T / (N - 1): a NumPy float array at double, else a list of
    rows of decimal strings), "period" (T), "action" (F), "flux" (2F), "multiplier" and
    "stability_index" (Floquet), their error estimates, "status"; numbers as in evaluate().
    `method` may name the integrator after a slash: "periodic/gauss-legendre", "symmetric/taylor"
    (default: Gauss-Legendre at double, Taylor series above; the same for evaluate()'s orbit
    quantities)."""
    r = _flipflux.saddle_orbit(_text(energy, "energy"), _text(arm, "arm"), precision, int(samples),
                               method, _parameters(pendulum))
    p = r["precision"]
    out = {"precision": p, "energy": r["energy"], "status": r["status"]}
    for k in ("period", "action", "flux", "multiplier", "stability_index",
              "error_estimate_period", "error_estimate_action", "energy_error"):
        out[k] = _number(r[k], p)
        out[k + "_text"] = r[k]
    out["samples"] = (_np.array(r["samples"], dtype=float) if p == "double"
                      else [list(row) for row in r["samples"]])
    return out


def simulate(energy, trajectories, time, arm=None, criteria=None, seed=None, rtol=None,
             method=None, threads=None, chaos=None, chaos_threshold=None, pendulum=None,
             replicates=None, max_seconds=None):
    """A Monte Carlo study -- `flipflux simulate` (at double). energy: one value, a list, or a
    "FROM:TO:STEP" string. Returns (report, trajectories): the study's JSON report as a dict (what
    the command-line tool prints; with replicates R > 1, `trajectories` each, every statistic
    also with its spread over the replicates) and, per energy label, the per-trajectory results as NumPy
    structured arrays (the columns of the --csv-dir trajectory files). Ctrl-C stops it;
    max_seconds bounds the integration's CPU seconds (every thread's): at the bound it stops with
    TimeoutError."""
    if isinstance(energy, (list, tuple)):
        energy = ",".join(_text(e, "energy") for e in energy)
    else:
        energy = _text(energy, "energy")
    if isinstance(criteria, (list, tuple)):
        criteria = ",".join(criteria)
    given = {"trajectories": trajectories, "time": time, "arm": arm, "seed": seed, "rtol": rtol,
             "threads": threads, "chaos_threshold": chaos_threshold, "replicates": replicates,
             "max_seconds": max_seconds}
    args = {k: _text(v, k) for k, v in given.items() if v is not None}
    args["energy"] = energy
    if criteria is not None:
        args["criteria"] = criteria
    if method is not None:
        args["method"] = method
    if chaos is not None:
        args["chaos"] = "true" if chaos else "false"
    report, tables = _flipflux.simulate(args, _parameters(pendulum))
    per_trajectory = {name: _structured(columns) for name, columns in sorted(tables.items())}
    return report, per_trajectory



if simulate.__doc__:  # None under python -OO
    simulate.__doc__ += (
        "\n\n    Settings left None take the library's defaults (its one settings table): " +
        ", ".join(f"{k}={v}" for k, v in _flipflux.run_settings() if v) + ".")

def _structured(columns):
    """A table of the library's study_files (a list of (column, values): NumPy int64 or float64
    arrays, lists of str) as a NumPy structured array with those columns, in order: the columns of
    the --csv-dir file of the same name."""
    rows = len(columns[0][1]) if columns else 0
    dtype = []
    for name, values in columns:
        if isinstance(values, _np.ndarray):
            dtype.append((name, values.dtype))
        else:
            dtype.append((name, f"<U{max([1] + [len(v) for v in values])}"))
    out = _np.empty(rows, dtype=dtype)
    for name, values in columns:
        out[name] = values
    return out


def golden_dir():
    """The golden data of this installation: share/flipflux/golden above the package (build tree:
    BUILD/share/flipflux/golden; installed: PREFIX/share/flipflux/golden), or None."""
    here = _os.path.dirname(_os.path.abspath(__file__))
    while True:
        candidate = _os.path.join(here, "share", "flipflux", "golden")
        if _os.path.isdir(candidate):
            return candidate
        parent = _os.path.dirname(here)
        if parent == here:
            return None
        here = parent


def validate(rows, rtol=1e-12, allow_missing=False, golden=None, pendulum=None):
    """Compares your values with the golden data -- `flipflux validate`. rows: an iterable of
    (quantity, arm, energy, value) tuples or of dicts with those keys (arm None or "" for omega;
    numbers as described in the module's docstring, str to keep every digit). pendulum: the
    golden set of another pendulum (a folder of the golden data, e.g. "unequal-point-masses";
    None or "egalitarian": the paper's). Returns a dict: "passed", "rows" (one dict per row:
    status ok/FAIL/unmatched/duplicate/malformed/missing, relative_error, matched_digits, ...) and
    "report" (the command-line tool's report)."""
    golden = golden or golden_dir()
    if golden is None:
        raise ValueError("golden: no golden data found above the package; give the directory")
    if pendulum not in (None, "egalitarian"):
        if not _os.path.isfile(_os.path.join(str(golden), str(pendulum), "golden.csv")) or \
                _os.sep in str(pendulum) or str(pendulum).startswith("."):
            raise ValueError(f"pendulum: '{pendulum}' has no golden set under '{golden}'")
        golden = _os.path.join(str(golden), str(pendulum))
    text = _io.StringIO()  # the rows as CSV in memory: no file in between
    w = _csv.writer(text, lineterminator="\n")
    w.writerow(["quantity", "arm", "energy", "value"])
    for row in rows:
        if isinstance(row, dict):
            row = (row["quantity"], row.get("arm"), row["energy"], row["value"])
        q, a, e, v = row
        w.writerow([q, "" if a is None else str(a), _text(e, "energy"), _text(v, "value")])
    return _flipflux.validate_rows(text.getvalue(), str(golden), float(rtol), bool(allow_missing))
