// The saddle-orbit viewer's page: one self-contained HTML file (no network access, no CDN, no
// external file), the data embedded as JSON (study/saddle_viewer.hpp viewer_json), drawn by plain
// JavaScript into SVG: an arm selector and an energy slider over the families, the orbit in
// configuration space (theta1, theta2) over the potential's contours (marching squares on the
// embedded grid), the pendulum animated along the orbit (two links, masses labelled m1 and m2),
// and the selected orbit's E, T, F and Floquet multiplier as text.
//
// Elements a test may read (tests/viewer/test_viewer_browser.py): #arm (select), #energy (range
// input; an `input` event redraws), #orbit (the orbit's SVG path: `d`), #period, #action,
// #multiplier, #energy-value (text), #pendulum (the animated drawing).
#pragma once

#include <string>

namespace flipflux {

/// The page with `data_json` embedded (every '<' escaped, so no text inside it can close the
/// script element) and `title` (HTML-escaped) as its title.
std::string viewer_page(const std::string& data_json, const std::string& title);

}  // namespace flipflux
