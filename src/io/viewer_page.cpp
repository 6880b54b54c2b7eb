// The saddle-orbit viewer's page (include/flipflux/io/viewer_page.hpp): HTML, CSS and plain
// JavaScript, nothing loaded from elsewhere. The only URL in it is the SVG namespace name, which
// createElementNS needs and which no browser fetches.
#include "flipflux/io/viewer_page.hpp"

#include <string>

namespace flipflux {
namespace {

// clang-format off
const char* const page_head = R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>@TITLE@</title>
<style>
body { font-family: sans-serif; margin: 16px; color: #222; background: #fff; }
h1 { font-size: 20px; margin: 0 0 8px 0; }
#controls { display: flex; gap: 16px; align-items: center; flex-wrap: wrap; margin-bottom: 8px; }
#energy { width: 420px; }
#views { display: flex; gap: 16px; flex-wrap: wrap; }
svg { border: 1px solid #ccc; background: #fcfcfc; }
#readout { font-family: monospace; font-size: 14px; margin-top: 8px; line-height: 1.5; }
#readout span { font-weight: bold; }
.note { color: #666; font-size: 12px; }
</style>
</head>
<body>
<h1>@TITLE@</h1>
<div id="controls">
  <label>arm <select id="arm"></select></label>
  <label>energy <input type="range" id="energy" min="0" max="0" step="1" value="0"></label>
  <span>E = <span id="energy-value"></span></span>
  <button id="play" type="button">pause</button>
  <label>speed <select id="speed"><option value="0.5">0.5</option><option value="1" selected>1</option><option value="2">2</option><option value="4">4</option></select> time units per second</label>
</div>
<div id="views">
  <svg id="configuration" width="560" height="590" viewBox="0 0 560 590" role="img" aria-label="the orbit in configuration space"></svg>
  <svg id="pendulum" width="420" height="420" viewBox="0 0 420 420" role="img" aria-label="the pendulum along the orbit"></svg>
</div>
<div id="readout">
  arm <span id="arm-value"></span>, E = <span id="energy-text"></span>
  (E &minus; E<sub>s</sub> = <span id="excess"></span>, E<sub>max</sub> = <span id="maximum"></span>)<br>
  period T = <span id="period"></span><br>
  action F = &#8750; l&middot;d&theta; = <span id="action"></span> (saddle flux f<sub>3</sub> = 2F = <span id="flux"></span>)<br>
  Floquet multiplier <span id="multiplier"></span> (stability index &mu; + 1/&mu; = <span id="stability"></span>)<br>
  t / T = <span id="phase"></span>
</div>
<p class="note" id="notes">Left: contours of the potential V(&theta;<sub>1</sub>, &theta;<sub>2</sub>) (grey), the level V = E bounding the allowed region (blue; the orbit turns on it), the saddle orbit (red) and the current configuration (black dot); angles from the downward vertical. Right: the pendulum moving along the orbit (the paths of both masses faint). Data: flipflux, precision <span id="precision"></span>; every number embedded with all its digits.</p>
<noscript>This page draws with JavaScript.</noscript>
<script type="application/json" id="viewer-data">)HTML";

const char* const page_tail = R"HTML(</script>
<script>
"use strict";
(function () {
  const DATA = JSON.parse(document.getElementById("viewer-data").textContent);
  const SVGNS = "http://www.w3.org/2000/svg";
  const $ = (id) => document.getElementById(id);
  const fmt = (x, p) => String(Number(Number(x).toPrecision(p || 12)));
  function el(parent, name, attrs, text) {
    const e = document.createElementNS(SVGNS, name);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    parent.appendChild(e);
    return e;
  }

  // ---- configuration space: theta1 to the right, theta2 up ----------------------------------
  const G = DATA.potential, n = G.n, from = G.from, to = G.to;
  const M = 50, P = 480;  // margin and plot size in pixels
  const X = (t1) => M + (t1 - from) / (to - from) * P;
  const Y = (t2) => M + P - (t2 - from) / (to - from) * P;
  const config = $("configuration");
  el(config, "rect", {x: M, y: M, width: P, height: P, fill: "#fff", stroke: "#999"});
  const clip = el(el(config, "defs", {}), "clipPath", {id: "plot-area"});
  el(clip, "rect", {x: M, y: M, width: P, height: P});

  // marching squares on the embedded grid: the level set V = level as one SVG path
  function contourPath(level) {
    const v = G.values, step = P / (n - 1), parts = [];
    const px = (i) => (M + i * step).toFixed(2), py = (j) => (M + P - j * step).toFixed(2);
    for (let i = 0; i + 1 < n; i++) {
      for (let j = 0; j + 1 < n; j++) {
        const a = v[i * n + j] - level, b = v[(i + 1) * n + j] - level;
        const c = v[(i + 1) * n + j + 1] - level, e = v[i * n + j + 1] - level;
        const pts = [];
        const cross = (p, q, pi, pj, qi, qj) => {
          if ((p < 0) !== (q < 0)) {
            const t = p / (p - q);
            pts.push([pi + (qi - pi) * t, pj + (qj - pj) * t]);
          } else {
            pts.push(null);
          }
        };
        cross(a, b, i, j, i + 1, j);              // edge ab (theta2 = j)
        cross(b, c, i + 1, j, i + 1, j + 1);      // edge bc (theta1 = i + 1)
        cross(c, e, i + 1, j + 1, i, j + 1);      // edge ce (theta2 = j + 1)
        cross(e, a, i, j + 1, i, j);              // edge ea (theta1 = i)
        const found = pts.filter((q) => q !== null);
        const seg = (p, q) => parts.push("M" + px(p[0]) + " " + py(p[1]) + "L" + px(q[0]) + " " + py(q[1]));
        if (found.length === 2) {
          seg(found[0], found[1]);
        } else if (found.length === 4) {
          // a saddle cell: the centre's sign decides which corners the level separates
          if (((a + b + c + e) / 4 < 0) === (a < 0)) { seg(pts[0], pts[1]); seg(pts[2], pts[3]); }
          else { seg(pts[3], pts[0]); seg(pts[1], pts[2]); }
        }
      }
    }
    return parts.join("");
  }

  const contours = el(config, "g", {"clip-path": "url(#plot-area)", fill: "none"});
  const emax = DATA.maximum_energy;
  const levels = [];
  for (let k = 1; k <= 11; k++) levels.push(emax * k / 12);
  for (const f of DATA.families) levels.push(f.saddle_energy);
  for (const level of levels)
    el(contours, "path", {d: contourPath(level), stroke: "#bbb", "stroke-width": 1, class: "contour"});
  const boundary = el(contours, "path", {id: "boundary", stroke: "#1f77b4", "stroke-width": 1.5});
  const orbit = el(config, "path", {id: "orbit", fill: "none", stroke: "#d62728", "stroke-width": 3, "clip-path": "url(#plot-area)"});
  const point = el(config, "circle", {id: "orbit-point", r: 5, fill: "#000"});

  // axes: ticks at multiples of pi/2
  const names = {"-2": "\u2212\u03c0", "-1": "\u2212\u03c0/2", "0": "0", "1": "\u03c0/2", "2": "\u03c0", "3": "3\u03c0/2", "4": "2\u03c0"};
  for (let k = Math.ceil(from / (Math.PI / 2) - 1e-9); k * Math.PI / 2 <= to + 1e-9; k++) {
    const t = k * Math.PI / 2, label = names[String(k)] || (k / 2 + "\u03c0");
    el(config, "line", {x1: X(t), y1: M + P, x2: X(t), y2: M + P + 6, stroke: "#333"});
    el(config, "text", {x: X(t), y: M + P + 20, "text-anchor": "middle", "font-size": 12}, label);
    el(config, "line", {x1: M - 6, y1: Y(t), x2: M, y2: Y(t), stroke: "#333"});
    el(config, "text", {x: M - 9, y: Y(t) + 4, "text-anchor": "end", "font-size": 12}, label);
  }
  el(config, "text", {x: M + P / 2, y: M + P + 40, "text-anchor": "middle", "font-size": 14}, "\u03b8\u2081 (arm 1)");
  el(config, "text", {x: 14, y: M + P / 2, "text-anchor": "middle", "font-size": 14, transform: "rotate(-90 14 " + (M + P / 2) + ")"}, "\u03b8\u2082 (arm 2)");
  for (const f of DATA.families) {
    el(config, "circle", {cx: X(f.saddle[0]), cy: Y(f.saddle[1]), r: 3, fill: "#555"});
    el(config, "text", {x: X(f.saddle[0]) + 6, y: Y(f.saddle[1]) - 6, "font-size": 11, fill: "#555"}, "saddle (arm " + f.arm + ")");
  }
  el(config, "text", {x: M + 4, y: M + 16, "font-size": 12}, "V(\u03b8\u2081, \u03b8\u2082), E_max = " + fmt(emax, 6));

  // ---- the pendulum ------------------------------------------------------------------------
  const par = DATA.parameters;
  const reach = par.L1 + Math.max(par.L2, par.a2);
  const S = 180 / reach, CX = 210, CY = 210;
  const pend = $("pendulum");
  const trace1 = el(pend, "path", {id: "trace1", fill: "none", stroke: "#9ecae1", "stroke-width": 1});
  const trace2 = el(pend, "path", {id: "trace2", fill: "none", stroke: "#fdae6b", "stroke-width": 1});
  const link1 = el(pend, "line", {id: "link1", stroke: "#333", "stroke-width": 4, "stroke-linecap": "round"});
  const link2 = el(pend, "line", {id: "link2", stroke: "#333", "stroke-width": 4, "stroke-linecap": "round"});
  el(pend, "circle", {cx: CX, cy: CY, r: 4, fill: "#333"});
  const rmass = (m) => 7 + 7 * Math.sqrt(m / Math.max(par.m1, par.m2));
  const mass1 = el(pend, "circle", {id: "mass1", r: rmass(par.m1), fill: "#1f77b4"});
  const mass2 = el(pend, "circle", {id: "mass2", r: rmass(par.m2), fill: "#ff7f0e"});
  const label1 = el(pend, "text", {id: "label1", "font-size": 14}, "m1");
  const label2 = el(pend, "text", {id: "label2", "font-size": 14}, "m2");
  el(pend, "text", {x: 8, y: 18, "font-size": 12}, "pivot at the centre; angles from the downward vertical");
  // screen positions: x to the right, y down (theta = 0 hangs down)
  function positions(t1, t2) {
    const j = [CX + S * par.L1 * Math.sin(t1), CY + S * par.L1 * Math.cos(t1)];
    return {
      joint: j,
      end: [j[0] + S * par.L2 * Math.sin(t2), j[1] + S * par.L2 * Math.cos(t2)],
      m1: [CX + S * par.a1 * Math.sin(t1), CY + S * par.a1 * Math.cos(t1)],
      m2: [j[0] + S * par.a2 * Math.sin(t2), j[1] + S * par.a2 * Math.cos(t2)],
    };
  }

  // ---- selection ---------------------------------------------------------------------------
  const armSelect = $("arm"), slider = $("energy");
  DATA.families.forEach((f, k) => {
    const o = document.createElement("option");
    o.value = String(k);
    o.textContent = "arm " + f.arm + (f.orbits.length ? "" : " (no orbit)");
    armSelect.appendChild(o);
  });
  $("precision").textContent = DATA.precision;
  $("maximum").textContent = fmt(emax);
  let family = null, current = null, phase = 0;

  function pathData(o) {
    const parts = [];
    for (let k = 0; k < o.theta1.length; k++)
      parts.push((k ? "L" : "M") + X(o.theta1[k]).toFixed(2) + " " + Y(o.theta2[k]).toFixed(2));
    return parts.join("");
  }
  function massPath(o, which) {
    const parts = [];
    for (let k = 0; k < o.theta1.length; k++) {
      const p = positions(o.theta1[k], o.theta2[k])[which];
      parts.push((k ? "L" : "M") + p[0].toFixed(2) + " " + p[1].toFixed(2));
    }
    return parts.join("");
  }

  function selectOrbit(index) {
    if (!family || !family.orbits.length) return;
    current = family.orbits[Math.max(0, Math.min(index, family.orbits.length - 1))];
    orbit.setAttribute("d", pathData(current));
    boundary.setAttribute("d", contourPath(current.energy));
    trace1.setAttribute("d", massPath(current, "m1"));
    trace2.setAttribute("d", massPath(current, "m2"));
    $("energy-value").textContent = String(current.energy);
    $("energy-text").textContent = String(current.energy);
    $("arm-value").textContent = String(family.arm);
    $("excess").textContent = fmt(current.energy - family.saddle_energy);
    $("period").textContent = fmt(current.period);
    $("action").textContent = fmt(current.action);
    $("flux").textContent = fmt(2 * current.action);
    $("stability").textContent = fmt(current.stability_index);
    $("multiplier").textContent = current.hyperbolic
        ? "\u03bc = " + fmt(current.multiplier) + " (hyperbolic)"
        : "|\u03bc| = 1, \u03bc = exp(\u00b1i\u03bd), \u03bd = " + fmt(current.angle) + " (elliptic)";
    draw();
  }

  function selectFamily(k) {
    const previous = family && family.orbits.length > 1 ? Number(slider.value) / (family.orbits.length - 1) : 0.5;
    family = DATA.families[k];
    const count = family.orbits.length;
    slider.max = String(Math.max(0, count - 1));
    slider.disabled = count === 0;
    slider.value = String(Math.round(previous * Math.max(0, count - 1)));
    if (count === 0) {
      orbit.setAttribute("d", "");
      $("period").textContent = "no orbit (" + family.stop_reason + ")";
      return;
    }
    selectOrbit(Number(slider.value));
  }

  // the pendulum and the marker at the phase t / T (linear interpolation between the samples,
  // which are at equal times)
  function draw() {
    if (!current) return;
    const m = current.theta1.length - 1, f = phase * m, k = Math.min(Math.floor(f), m - 1), w = f - k;
    const t1 = current.theta1[k] * (1 - w) + current.theta1[k + 1] * w;
    const t2 = current.theta2[k] * (1 - w) + current.theta2[k + 1] * w;
    const p = positions(t1, t2);
    link1.setAttribute("x1", CX); link1.setAttribute("y1", CY);
    link1.setAttribute("x2", p.joint[0]); link1.setAttribute("y2", p.joint[1]);
    link2.setAttribute("x1", p.joint[0]); link2.setAttribute("y1", p.joint[1]);
    link2.setAttribute("x2", p.end[0]); link2.setAttribute("y2", p.end[1]);
    mass1.setAttribute("cx", p.m1[0]); mass1.setAttribute("cy", p.m1[1]);
    mass2.setAttribute("cx", p.m2[0]); mass2.setAttribute("cy", p.m2[1]);
    label1.setAttribute("x", p.m1[0] + 14); label1.setAttribute("y", p.m1[1] - 10);
    label2.setAttribute("x", p.m2[0] + 14); label2.setAttribute("y", p.m2[1] - 10);
    point.setAttribute("cx", X(t1)); point.setAttribute("cy", Y(t2));
    $("phase").textContent = phase.toFixed(3);
  }

  // NOTE: a timer, not requestAnimationFrame: headless browsers (the test's) and background tabs
  // may never schedule animation frames; 20 ms steps advance the phase by the time elapsed
  let playing = true, last = performance.now();
  function tick() {
    const now = performance.now();
    if (playing && current) {
      const speed = Number($("speed").value);
      phase = (phase + (now - last) / 1000 * speed / current.period) % 1;
      draw();
    }
    last = now;
  }
  $("play").addEventListener("click", () => {
    playing = !playing;
    $("play").textContent = playing ? "pause" : "play";
  });
  slider.addEventListener("input", () => selectOrbit(Number(slider.value)));
  armSelect.addEventListener("change", () => selectFamily(Number(armSelect.value)));

  const start = Math.max(0, DATA.families.findIndex((f) => f.arm === 2 && f.orbits.length));
  armSelect.value = String(start);
  selectFamily(start);
  window.setInterval(tick, 20);
})();
</script>
</body>
</html>
)HTML";
// clang-format on

std::string html_escape(const std::string& text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t pos = text.find(from); pos != std::string::npos;
         pos = text.find(from, pos + to.size()))
        text.replace(pos, from.size(), to);
    return text;
}

}  // namespace

std::string viewer_page(const std::string& data_json, const std::string& title) {
    // NOTE: in valid JSON '<' occurs only inside strings, where \u003c means the same character;
    // so "</script>" can never appear in the embedded text
    return replace_all(page_head, "@TITLE@", html_escape(title)) +
           replace_all(data_json, "<", "\\u003c") + page_tail;
}

}  // namespace flipflux
