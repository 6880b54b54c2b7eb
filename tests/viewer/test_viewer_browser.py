#!/usr/bin/python3
"""The saddle-orbit viewer in a real browser (headless Chromium, Debian's `chromium`).

`flipflux viewer` writes a small page (both arms, a few orbits); the test then
  1. reads the page: self-contained (no http(s) URL but the SVG namespace name, no src=, no
     <link>), the embedded JSON parses and holds both families;
  2. loads it in Chromium (file://) with a probe script appended that uses only the page's DOM as
     a person would: the slider #energy exists; setting it to its last value and dispatching an
     `input` event must change the orbit's SVG path (#orbit `d`) and the displayed period
     (#period), which must equal the embedded period of the selected orbit; choosing the other arm
     (#arm, `change`) must change the path again; the pendulum must move (mass m2's position
     after some animation time) and its masses be labelled m1, m2. The probe writes what it saw
     into the DOM, which Chromium prints (--dump-dom) after the virtual time budget;
  3. takes a screenshot (--screenshot) and decodes the PNG with zlib (stdlib only): the right
     size, not blank (many colours, enough non-white pixels) and the orbit's red drawn.
Chromium runs as root here, hence --no-sandbox; a temporary --user-data-dir keeps it off $HOME.
Stdlib only (/usr/bin/python3). Prints its cost; ctest gives it a timeout.
"""
import argparse
import html
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                  "--no-first-run", "--no-default-browser-check", "--mute-audio"]

PROBE = r"""
<script>
window.addEventListener("load", function () {
  const out = {};
  const $ = (id) => document.getElementById(id);
  const slider = $("energy"), orbit = $("orbit"), arm = $("arm");
  out.slider = slider ? {type: slider.type, min: slider.min, max: slider.max, value: slider.value} : null;
  const state = () => ({d: orbit.getAttribute("d"), period: $("period").textContent,
                        energy: $("energy-value").textContent, arm: $("arm-value").textContent,
                        multiplier: $("multiplier").textContent});
  out.before = state();
  slider.value = slider.max;
  slider.dispatchEvent(new Event("input", {bubbles: true}));
  out.after = state();
  const other = Array.from(arm.options).find((o) => o.value !== arm.value);
  arm.value = other.value;
  arm.dispatchEvent(new Event("change", {bubbles: true}));
  out.other_arm = state();
  out.labels = [$("label1").textContent, $("label2").textContent];
  out.mass2_start = [$("mass2").getAttribute("cx"), $("mass2").getAttribute("cy")];
  setTimeout(function () {
    out.mass2_later = [$("mass2").getAttribute("cx"), $("mass2").getAttribute("cy")];
    out.phase_later = $("phase").textContent;
    const pre = document.createElement("pre");
    pre.id = "probe-result";
    pre.textContent = JSON.stringify(out);
    document.body.appendChild(pre);
  }, 700);
});
</script>
"""


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def chromium(exe, profile, args, timeout):
    cmd = [exe] + CHROMIUM_FLAGS + ["--user-data-dir=" + profile] + args
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if r.returncode != 0:
        fail("chromium exited %d: %s\n%s" % (r.returncode, " ".join(cmd), r.stderr[-2000:]))
    return r.stdout


def png_pixels(path):
    """(width, height, rows of RGB tuples) of an 8-bit RGB or RGBA non-interlaced PNG."""
    data = open(path, "rb").read()
    check(data[:8] == b"\x89PNG\r\n\x1a\n", "the screenshot is not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            check(depth == 8 and colour in (2, 6) and interlace == 0,
                  "unexpected PNG format (depth %d, colour type %d)" % (depth, colour))
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous, i = [], bytearray(stride), 0
    for _ in range(height):
        filt, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if filt == 1:
                line[x] = (line[x] + a) & 255
            elif filt == 2:
                line[x] = (line[x] + b) & 255
            elif filt == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif filt == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x:x + 3]) for x in range(0, stride, channels)])
        previous = line
    return width, height, rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flipflux", required=True)
    ap.add_argument("--chromium", default="chromium")
    ap.add_argument("--keep", help="copy the page and the screenshot into this folder")
    args = ap.parse_args()
    exe = shutil.which(args.chromium)
    check(exe is not None, "'%s' not found: install Debian's chromium (bash setup.sh does)"
          % args.chromium)
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="flipflux-viewer-") as tmp:
        out = os.path.join(tmp, "out")
        r = subprocess.run([args.flipflux, "viewer", "--out", out, "--arms", "1,2",
                            "--energies", "3", "--samples", "81", "--grid", "49"],
                           capture_output=True, text=True, timeout=600)
        check(r.returncode == 0, "flipflux viewer failed: " + r.stderr)
        computed = time.monotonic()
        page_file = os.path.join(out, "viewer.html")
        page = open(page_file, encoding="utf-8").read()

        # 1. the page itself
        check("https:" not in page and "<link" not in page and " src=" not in page,
              "the page refers to something outside itself")
        check(re.findall(r"http:[^\"']*", page) == ["http://www.w3.org/2000/svg"],
              "a URL other than the SVG namespace name: %s" % re.findall(r"http:[^\"']*", page))
        m = re.search(r'<script type="application/json" id="viewer-data">(.*?)</script>', page,
                      re.S)
        check(m is not None, "no embedded data")
        data = json.loads(m.group(1))
        check([f["arm"] for f in data["families"]] == [1, 2], "families: %s" % data["families"])
        for f in data["families"]:
            check(len(f["orbits"]) == 3, "arm %d: %d orbits" % (f["arm"], len(f["orbits"])))

        # 2. the DOM, moved as a person would
        probe_file = os.path.join(tmp, "probe.html")
        with open(probe_file, "w", encoding="utf-8") as f:
            f.write(page.replace("</body>", PROBE + "</body>"))
        dom = chromium(exe, os.path.join(tmp, "profile-dom"),
                       ["--virtual-time-budget=3000", "--dump-dom", "file://" + probe_file], 120)
        m = re.search(r'<pre id="probe-result">(.*?)</pre>', dom, re.S)
        check(m is not None, "the probe wrote nothing (did the page's script fail?)\n" + dom[-1500:])
        seen = json.loads(html.unescape(m.group(1)))
        print("probe:", json.dumps({k: v for k, v in seen.items() if k in
                                    ("slider", "labels", "mass2_start", "mass2_later")}))
        check(seen["slider"] is not None and seen["slider"]["type"] == "range",
              "no range slider #energy")
        check(seen["slider"]["min"] == "0" and seen["slider"]["max"] == "2",
              "slider range %s" % seen["slider"])
        before, after, other = seen["before"], seen["after"], seen["other_arm"]
        check(before["arm"] == "2" and after["arm"] == "2" and other["arm"] == "1",
              "arms shown: %s %s %s" % (before["arm"], after["arm"], other["arm"]))
        check(before["d"].startswith("M") and len(before["d"]) > 100, "no orbit drawn")
        check(after["d"] != before["d"], "moving the slider did not change the drawn orbit")
        check(after["period"] != before["period"], "moving the slider did not change the period")
        check(other["d"] != after["d"], "choosing arm 1 did not change the drawn orbit")
        arm2 = data["families"][1]["orbits"]
        for shown, orbit in ((before, arm2[1]), (after, arm2[2]),
                             (other, data["families"][0]["orbits"][2])):
            check(abs(float(shown["period"]) / orbit["period"] - 1) < 1e-11,
                  "displayed period %s, embedded %r" % (shown["period"], orbit["period"]))
            check(abs(float(shown["energy"]) - orbit["energy"]) == 0,
                  "displayed energy %s, embedded %r" % (shown["energy"], orbit["energy"]))
        check(float(after["period"]) > float(before["period"]),
              "the period does not grow with the energy along arm 2's family")
        check(seen["labels"] == ["m1", "m2"], "mass labels %s" % seen["labels"])
        check(seen["mass2_later"] != seen["mass2_start"], "the pendulum does not move")

        # 3. the screenshot
        shot = os.path.join(tmp, "viewer.png")
        chromium(exe, os.path.join(tmp, "profile-shot"),
                 ["--window-size=1100,800", "--virtual-time-budget=1000",
                  "--screenshot=" + shot, "file://" + page_file], 120)
        width, height, rows = png_pixels(shot)
        check((width, height) == (1100, 800), "screenshot size %dx%d" % (width, height))
        colours, ink, red = set(), 0, 0
        for row in rows:
            for p in row:
                colours.add(p)
                if min(p) < 235:
                    ink += 1
                if abs(p[0] - 214) < 30 and abs(p[1] - 39) < 40 and abs(p[2] - 40) < 40:
                    red += 1
        total = width * height
        print("screenshot: %d colours, %.1f %% ink, %d orbit-red pixels" %
              (len(colours), 100.0 * ink / total, red))
        check(len(colours) >= 50, "the screenshot is nearly blank (%d colours)" % len(colours))
        check(ink >= total // 50, "the screenshot is nearly blank (%d drawn pixels)" % ink)
        check(red >= 200, "the orbit (red) is not visible in the screenshot (%d pixels)" % red)
        if args.keep:
            os.makedirs(args.keep, exist_ok=True)
            shutil.copy(page_file, args.keep)
            shutil.copy(shot, args.keep)
    end = time.monotonic()
    print("viewer browser test: flipflux viewer %.1f s, browser and checks %.1f s, total %.1f s"
          % (computed - start, end - computed, end - start))


if __name__ == "__main__":
    main()
