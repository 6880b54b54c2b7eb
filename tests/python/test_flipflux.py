"""The Python module (python/, docs/python.md) against the command-line tool: the same digits at
every precision, exact inputs, mpmath round trips, errors, validation, simulation, and the
docs/python.md example. Run by ctest (python_module, label unit) with PYTHONPATH=BUILD/python,
FLIPFLUX_EXE (the CLI) and FLIPFLUX_SOURCE_DIR set."""
import csv
import json
import os
import re
import subprocess
import tempfile
from fractions import Fraction

import mpmath
import numpy as np
import pytest

import flipflux

EXE = os.environ["FLIPFLUX_EXE"]
SOURCE = os.environ["FLIPFLUX_SOURCE_DIR"]
# The CLI without the sanitizer runtime preloaded into this interpreter (a sanitized build): a
# clang-built executable carries its own, and two ASan runtimes in one process are refused.
CLI_ENV = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}


def cli(*args, check=True):
    r = subprocess.run([EXE, *args], capture_output=True, text=True, env=CLI_ENV)
    if check:
        assert r.returncode == 0, r.stderr
    return r


def cli_eval(*args):
    return json.loads(cli("eval", *args).stdout)


@pytest.mark.parametrize("precision", ["double", "quad", "mp:50"])
@pytest.mark.parametrize("quantity,energy,arm", [("omega", "3", 2), ("rate-upright", "4.5", 1),
                                                 ("flux-approx", "2.5", 2)])
def test_evaluate_equals_cli_digit_for_digit(quantity, energy, arm, precision):
    v = flipflux.evaluate(quantity, energy, arm=arm, precision=precision)
    c = cli_eval(quantity, "--energy", energy, "--arm", str(arm), "--precision", precision)
    assert v.text == c["value"]
    assert v.error_text == c["error_estimate"]
    assert v.method == c["method"] and v.precision == c["precision"]
    assert str(v) == f"{c['value']} +- {c['error_estimate']} ({c['method']}, {precision})"
    if precision == "double":
        assert isinstance(v.value, float) and v.value == float(c["value"])
    else:
        assert isinstance(v.value, mpmath.mpf)


def test_evaluate_method_and_pendulum_equal_cli():
    p = flipflux.Pendulum(m2="0.5", L2="2", a1="0.75", I1="0.01")
    v = flipflux.evaluate("omega", "4", precision="quad", method="quadrature-2d", pendulum=p)
    c = cli_eval("omega", "--energy", "4", "--precision", "quad", "--method", "quadrature-2d",
                 "--m2", "0.5", "--L2", "2", "--a1", "0.75", "--I1", "0.01")
    assert v.text == c["value"] and v.method == c["method"]


def test_mp50_value_round_trips_through_mpmath():
    v = flipflux.evaluate("omega", "3", precision="mp:50")
    digits = len(re.sub(r"[^0-9]", "", v.text.split("e")[0]).lstrip("0"))
    assert digits == 52  # mp:N prints N + 2 significant digits
    assert mpmath.mp.dps >= digits
    # the mpf holds every digit: printed back at the string's digits it is the same number
    back = mpmath.nstr(v.value, digits, strip_zeros=False, min_fixed=-mpmath.inf,
                       max_fixed=mpmath.inf)
    assert mpmath.mpf(back) == mpmath.mpf(v.text)
    assert back.rstrip("0") == v.text.rstrip("0")


def test_float_energy_is_its_exact_binary_value():
    exact = "0.1000000000000000055511151231257827021181583404541015625"
    v = flipflux.evaluate("omega", 0.1, precision="quad")
    assert v.text == cli_eval("omega", "--energy", exact, "--precision", "quad")["value"]
    assert v.text != flipflux.evaluate("omega", "0.1", precision="quad").text
    assert flipflux._text(mpmath.mpf(0.375), "x") == "0.375"
    for x in (2.5e-3, 1 / 3, 6.02e23, -7.5e-300):  # Fraction(float) is the float's exact value
        assert Fraction(flipflux._text(x, "x")) == Fraction(x)


def cli_orbit_rows(energy, precision, samples):
    return cli("orbit", "--energy", energy, "--arm", "2", "--samples", str(samples),
               "--precision", precision).stdout.strip().split("\n")[1:]


def test_saddle_orbit_equals_cli_at_double():
    o = flipflux.saddle_orbit("4", arm=2, samples=3)
    rows = cli_orbit_rows("4", "double", 3)
    assert o["samples"].shape == (3, 5)
    assert np.array_equal(o["samples"], np.array([[float(x) for x in r.split(",")]
                                                  for r in rows]))
    for name in ("period", "action", "multiplier", "stability-index", "flux-saddle"):
        c = cli_eval(name, "--energy", "4", "--arm", "2")
        key = {"stability-index": "stability_index", "flux-saddle": "flux"}.get(name, name)
        assert o[key + "_text"] == c["value"], name
        assert o[key] == float(c["value"]), name


def test_saddle_orbit_equals_cli_at_quad():
    # E = 2.2: the cheapest quad orbit (~1 s optimised; the CI build is -O0 with sanitizers)
    o = flipflux.saddle_orbit("2.2", arm=2, precision="quad", samples=3)
    rows = cli_orbit_rows("2.2", "quad", 3)
    assert [",".join(r) for r in o["samples"]] == rows
    assert o["samples"][-1][0] == o["period_text"]  # the last row is at t = T
    assert isinstance(o["period"], mpmath.mpf) and o["period"] == mpmath.mpf(o["period_text"])


def test_saddle_orbit_integrator_in_the_method():
    # the independent route at double is Taylor (Gauss-Legendre is the default there)
    t = flipflux.saddle_orbit("2.2", arm=2, samples=2, method="symmetric/taylor")
    g = flipflux.saddle_orbit("2.2", arm=2, samples=2, method="symmetric/gauss-legendre")
    assert abs(t["period"] - g["period"]) <= t["error_estimate_period"] + g["error_estimate_period"]
    v = flipflux.evaluate("period", "2.2", method="symmetric/taylor")
    assert "Taylor" in v.method
    with pytest.raises(ValueError) as e:
        flipflux.saddle_orbit("2.2", method="periodic/rk4")
    assert str(e.value).startswith("method: ")


@pytest.mark.parametrize("call,args", [
    ("eval", lambda: flipflux.evaluate("omega", "-x")),
    ("eval", lambda: flipflux.evaluate("omega", "3", arm=3)),
    ("eval", lambda: flipflux.evaluate("no-such-quantity", "3")),
    ("eval", lambda: flipflux.evaluate("omega", "3", precision="mp:0")),
    ("eval", lambda: flipflux.evaluate("omega", "3", pendulum=flipflux.Pendulum(m1="-1"))),
    ("orbit", lambda: flipflux.saddle_orbit("1", arm=2)),
])
def test_bad_input_raises_value_error_with_the_cli_message(call, args):
    with pytest.raises(ValueError) as e:
        args()
    message = str(e.value)
    assert "\n" not in message and message


def test_bad_input_messages_match_cli_exactly():
    """The same one-line message as the command line's, naming the Python keyword where the
    command line names its option."""
    cases = [
        (lambda: flipflux.evaluate("omega", "abc"), "energy", ["eval", "omega", "--energy", "abc"]),
        (lambda: flipflux.evaluate("omega", "3", arm=3), "arm",
         ["eval", "omega", "--energy", "3", "--arm", "3"]),
        (lambda: flipflux.evaluate("nope", "3"), None, ["eval", "nope", "--energy", "3"]),
        (lambda: flipflux.evaluate("omega", "3", pendulum=flipflux.Pendulum(m1="-1")), "m1",
         ["eval", "omega", "--energy", "3", "--m1", "-1"]),
        (lambda: flipflux.saddle_orbit("1"), "energy", ["orbit", "--energy", "1"]),
        (lambda: flipflux.simulate(5, 0, 10), "trajectories",
         ["simulate", "--energy", "5", "--trajectories", "0", "--time", "10"]),
        (lambda: flipflux.simulate(5, 10, 10, rtol="1e-30"), "rtol",
         ["simulate", "--energy", "5", "--trajectories", "10", "--time", "10", "--rtol", "1e-30"]),
        (lambda: flipflux.simulate(5, 10, 10, chaos_threshold=-1), "chaos_threshold",
         ["simulate", "--energy", "5", "--trajectories", "10", "--time", "10",
          "--chaos-threshold", "-1"]),
    ]
    for call, keyword, args in cases:
        with pytest.raises(ValueError) as e:
            call()
        message = str(e.value)
        r = cli(*args, check=False)
        assert r.returncode == 2
        if keyword is None:
            assert r.stderr.strip() == "flipflux: error: " + message
        else:
            assert message.startswith(keyword + ": "), message
            option = "--" + keyword.replace("_", "-")
            assert r.stderr.strip() == "flipflux: error: " + option + message[len(keyword):]


def test_validate_rows():
    golden = os.path.join(SOURCE, "data", "golden", "golden.csv")
    rows = []
    with open(golden) as f:
        next(f)
        for line in f:
            q, a, e, v = line.split(",")[:4]
            if q == "omega":
                rows.append({"quantity": q, "arm": None, "energy": e, "value": v[:25]})
    assert flipflux.golden_dir() is not None
    r = flipflux.validate(rows, rtol=1e-20)
    assert r["passed"] and len(r["rows"]) == len(rows)
    assert all(row["status"] == "ok" for row in r["rows"])
    rows[0] = ("omega", "", rows[0]["energy"], "1.5")
    bad = flipflux.validate(rows, rtol=1e-20)
    assert not bad["passed"] and bad["rows"][0]["status"] == "FAIL"
    with pytest.raises(ValueError):
        flipflux.validate(rows, rtol=2)


def test_simulate_equals_cli():
    report, per_trajectory = flipflux.simulate(["3", "5"], trajectories=6, time=10, seed=7,
                                               chaos=False, threads=1)
    c = json.loads(cli("simulate", "--energy", "3,5", "--trajectories", "6", "--time", "10",
                       "--seed", "7", "--no-chaos", "--threads", "1").stdout)
    for mine, theirs in zip(report["energies"], c["energies"]):
        assert mine["criteria"] == theirs["criteria"]
    assert report["model"] == c["model"]
    assert per_trajectory, "no per-trajectory arrays"
    for name, a in per_trajectory.items():
        assert isinstance(a, np.ndarray) and a.dtype.names, name
    # the CLI's files, column by column: the same numbers; lyapunov, empty in the file (not
    # computed without the chaos indicator), is NaN, not genfromtxt's False
    with tempfile.TemporaryDirectory() as d:
        cli("simulate", "--energy", "3,5", "--trajectories", "6", "--time", "10", "--seed", "7",
            "--no-chaos", "--threads", "1", "--csv-dir", d)
        for name, a in per_trajectory.items():
            with open(os.path.join(d, name + ".csv"), newline="") as f:
                rows = list(csv.DictReader(f))
            assert len(rows) == a.size, name
            for field in a.dtype.names:
                for row, value in zip(rows, np.atleast_1d(a[field])):
                    if row[field] == "":
                        assert np.isnan(value), (name, field)
                    elif a.dtype[field].kind == "f":
                        assert value == float(row[field]), (name, field)
                    elif a.dtype[field].kind == "i":
                        assert value == int(row[field]), (name, field)
                    else:
                        assert value == row[field], (name, field)
        # one array per file, built from the library's tables (no file in between)
        assert set(per_trajectory) == {os.path.splitext(n)[0] for n in os.listdir(d)}
        lyapunov = [a["lyapunov"] for a in per_trajectory.values() if "lyapunov" in a.dtype.names]
        assert lyapunov and all(np.all(np.isnan(x)) for x in lyapunov)
    for kwargs, args in ((dict(trajectories=0), ["--trajectories", "0"]),
                         (dict(trajectories=-5), ["--trajectories", "-5"]),
                         (dict(trajectories=2.5), ["--trajectories", "2.5"]),
                         (dict(trajectories=4, seed=-1), ["--trajectories", "4", "--seed", "-1"]),
                         (dict(trajectories=4, arm=3), ["--trajectories", "4", "--arm", "3"])):
        with pytest.raises(ValueError) as e:
            flipflux.simulate("3", time=10, **kwargs)
        r = cli("simulate", "--energy", "3", "--time", "10", *args, check=False)
        # the same message, naming the keyword where the command line names its option
        option = args[-2]
        keyword = option[2:].replace("-", "_")
        assert str(e.value).startswith(keyword + ": "), str(e.value)
        assert r.returncode == 2
        assert r.stderr.strip() == "flipflux: error: " + option + str(e.value)[len(keyword):]


def test_python_md_example():
    text = open(os.path.join(SOURCE, "docs", "python.md")).read()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1 and 15 <= len(blocks[0].strip().splitlines()) <= 40
    exec(compile(blocks[0], "docs/python.md", "exec"), {})


@pytest.mark.parametrize("call", [
    "flipflux.simulate('5', trajectories=100000, time=1000, threads=1)",
    "flipflux.evaluate('period', '3', precision='mp:400')",
])
def test_ctrl_c_interrupts_a_long_call(call):
    """SIGINT during a long call raises KeyboardInterrupt within a second (the call polls every
    50 ms with the GIL released); simulate stops its trajectories, evaluate is abandoned (the
    child ends with os._exit: the abandoned computation is still running, docs/python.md)."""
    import signal
    import sys
    import time
    code = (f"import flipflux, os, time\nprint('ready', flush=True)\nt = time.monotonic()\n"
            f"try:\n    {call}\nexcept KeyboardInterrupt:\n"
            f"    print('interrupted after', time.monotonic() - t, flush=True)\n    os._exit(0)\n"
            f"print('finished', flush=True)\nos._exit(1)\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True,
                         env=os.environ)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 0, out
    assert "interrupted after" in out
    assert time.monotonic() - sent < 10


def test_pendulum_keywords_are_the_parameter_table():
    """Pendulum's keywords and defaults are model/'s parameter table (a1, a2: None, the length)."""
    import inspect
    sig = inspect.signature(flipflux.Pendulum.__init__)
    names = [p for p in sig.parameters if p != "self"]
    table = flipflux._flipflux.parameter_fields()
    assert names == [name for name, _ in table]
    for name, default in table:
        given = sig.parameters[name].default
        assert (given is None) if default == "" else (str(given) == default), name


def test_simulate_defaults_are_the_settings_table():
    """simulate's keywords left None take the library's defaults: the same report as the
    command line's defaults."""
    table = dict(flipflux._flipflux.run_settings())
    assert table["rtol"] == "1e-10" and table["seed"] == "0" and table["method"] == "auto"
    report, _ = flipflux.simulate(5, 4, 5, threads=1)
    r = cli("simulate", "--energy", "5", "--trajectories", "4", "--time", "5", "--threads", "1",
            "--no-timing")
    expected = json.loads(r.stdout)
    for key in ("rtol", "atol", "seed", "method", "arm", "estimator"):
        assert report[key] == expected[key], key
    assert report["chaos"]["threshold"] == expected["chaos"]["threshold"]
    assert report["chaos"]["indicator"] == expected["chaos"]["indicator"]


def test_simulate_max_seconds_bounds_the_run():
    """max_seconds bounds the integration's CPU seconds: a run of about 2 CPU seconds stops at
    0.05 with TimeoutError naming the keyword; a bound that is not a finite number >= 0 is a
    ValueError naming it."""
    with pytest.raises(TimeoutError, match=r"^max_seconds: stopped at its bound of 0.05 CPU"):
        flipflux.simulate(5, 4000, 100, criteria="upright", threads=1, chaos=False,
                          max_seconds=0.05)
    with pytest.raises(ValueError, match=r"^max_seconds: '-1' is invalid"):
        flipflux.simulate(5, 4, 1, max_seconds=-1)
