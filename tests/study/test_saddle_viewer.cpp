// The saddle-orbit viewer's data (study/saddle_viewer.hpp) and page (io/viewer_page.hpp): the
// energies, the request checks, an orbit's path (it closes, starts at the saddle, reaches the
// level V = E at its quarter period), its period against the symmetric shooting (`eval period
// --method symmetric`, an independent route), the potential grid at the critical points, the JSON
// and the page. Cheap at -O0: one orbit of one arm.
#include <nlohmann/json.hpp>

#include "flipflux/core/constants.hpp"
#include "flipflux/io/viewer_page.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/quantities/registry.hpp"
#include "flipflux/study/saddle_viewer.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

TEST(SaddleViewer, EnergiesAreEvenlySpacedInsideTheFamilysRange) {
    const double_pendulum<double> model;  // E_s = 2 (arm 2), 4 (arm 1), E_max = 6
    EXPECT_EQ(viewer_energy_texts(model, arm::two, 3), (std::vector<std::string>{"3", "4", "5"}));
    EXPECT_EQ(viewer_energy_texts(model, arm::one, 1), (std::vector<std::string>{"5"}));
    // 7 energies over (2, 6): 2 + 4 k / 8, exact binary fractions
    EXPECT_EQ(viewer_energy_texts(model, arm::two, 7),
              (std::vector<std::string>{"2.5", "3", "3.5", "4", "4.5", "5", "5.5"}));
    // a narrow family (arm 1 with a light link 2: E_max - E_s = 2 beta small): each text within
    // 1/100 of the spacing of E_s + (E_max - E_s) (k + 1) / (N + 1), increasing, inside
    physical_parameters<double> p;
    p.m2 = 1e-6;
    const double_pendulum<double> light(p);
    const double es = light.saddle_energy(arm::one), emax = light.maximum_energy();
    const auto texts = viewer_energy_texts(light, arm::one, 30);
    ASSERT_EQ(texts.size(), 30u);
    double previous = es;
    for (std::size_t k = 0; k < texts.size(); ++k) {
        const double e = parse_real<double>(texts[k], "energy");
        const double spacing = (emax - es) / 31;
        EXPECT_LE(std::abs(e - (es + spacing * double(k + 1))), spacing / 100) << texts[k];
        EXPECT_GT(e, previous);
        EXPECT_LT(e, emax);
        previous = e;
    }
}

TEST(SaddleViewer, BadRequestsNameTheirField) {
    auto field_of = [](const viewer_request& r) {
        try {
            check_viewer_request(r);
        } catch (const input_error& e) {
            return e.field();
        }
        return std::string("accepted");
    };
    viewer_request r;
    EXPECT_EQ(field_of(r), "accepted");
    r.energies = 0;
    EXPECT_EQ(field_of(r), "energies");
    r = {};
    r.samples = 7;
    EXPECT_EQ(field_of(r), "samples");
    r = {};
    r.grid = 120;  // not 1 mod 6
    EXPECT_EQ(field_of(r), "grid");
    r = {};
    r.grid = 1;
    EXPECT_EQ(field_of(r), "grid");
    r = {};
    r.arms = {arm::two, arm::two};
    EXPECT_EQ(field_of(r), "arms");
    r.arms = {};
    EXPECT_EQ(field_of(r), "arms");
}

TEST(SaddleViewer, OrbitPathClosesAndItsPeriodAgreesWithTheSymmetricShooting) {
    forget_saddle_orbits();
    const double_pendulum<double> model;
    viewer_request request;
    request.arms = {arm::two};
    request.energies = 1;  // E = 4
    request.samples = 41;  // t_k = k T / 40: k = 10 is the quarter period, a turning point
    request.grid = 13;     // nodes at multiples of pi / 4 over [-pi, 2 pi]
    const viewer_data<double> data = saddle_viewer_data(model, request);
    ASSERT_EQ(data.families.size(), 1u);
    const viewer_family<double>& fam = data.families[0];
    EXPECT_EQ(fam.flip_arm, arm::two);
    EXPECT_EQ(fam.stop_reason, "");
    ASSERT_EQ(fam.orbits.size(), 1u);
    EXPECT_EQ(data.solved, 1u);
    const viewer_orbit<double>& o = fam.orbits[0];
    EXPECT_EQ(o.energy, "4");
    ASSERT_EQ(o.path.size(), 41u);
    const double E = 4, pi_d = pi<double>();
    // the orbit starts at the saddle (0, pi) and closes after one period (the last point is
    // integrated to t = T, not copied): to the orbit's accuracy (measured: within 10 eps over
    // both families of 30 orbits each)
    EXPECT_NEAR(o.path.front()[0], 0, 16 * eps);
    EXPECT_NEAR(o.path.front()[1], pi_d, 16 * eps);
    const double tol = 256 * eps * pi_d;
    EXPECT_NEAR(o.path.back()[0], o.path.front()[0], tol);
    EXPECT_NEAR(o.path.back()[1], o.path.front()[1], tol);
    // every point in the allowed region V <= E; at t = T/4 and 3T/4 both momenta vanish, so
    // V = E there (the energy surface, a property of the path the solver does not impose on it;
    // measured: within 50 eps relative over both families of 30 orbits each)
    for (const auto& q : o.path)
        EXPECT_LE(model.potential(q[0], q[1]), E * (1 + 256 * eps));
    for (std::size_t k : {10u, 30u})
        EXPECT_NEAR(model.potential(o.path[k][0], o.path[k][1]), E, 256 * eps * E) << k;
    // the period by the other shooting formulation (time-reversal symmetry, Newton), via the
    // registry as `flipflux eval period --method symmetric`
    const quantity_value<double> sym =
        find_quantity("period").evaluate(model, arm::two, energy_level<double>(E), "symmetric");
    EXPECT_LE(std::abs(o.period - sym.value), o.error_estimate_period + sym.error_estimate)
        << to_decimal(o.period) << " vs " << to_decimal(sym.value);
    EXPECT_LE(std::abs(o.period - sym.value), 1e-12 * sym.value);
    EXPECT_GT(o.action, 0);
    EXPECT_TRUE(o.hyperbolic);
    EXPECT_NEAR(o.stability_index, o.multiplier + 1 / o.multiplier,
                64 * eps * std::abs(o.stability_index));
    // the potential grid: V(0, pi) is arm 2's saddle energy 2 beta, V(pi, pi) = E_max, V(0, 0) = 0
    const potential_grid<double>& g = data.potential;
    ASSERT_EQ(g.n, 13);
    ASSERT_EQ(g.values.size(), 169u);
    EXPECT_NEAR(g.from, -pi_d, 4 * eps);
    EXPECT_NEAR(g.to, 2 * pi_d, 8 * eps);
    EXPECT_NEAR(g.values[4 * 13 + 8], model.saddle_energy(arm::two), 8 * eps);
    EXPECT_NEAR(g.values[8 * 13 + 8], model.maximum_energy(), 16 * eps);
    EXPECT_NEAR(g.values[4 * 13 + 4], 0, 8 * eps);
    // a second request finds the orbit in the memo
    EXPECT_EQ(saddle_viewer_data(model, request).solved, 0u);

    // the JSON: every number read back is the double written (17 digits round-trip)
    const nlohmann::json j = nlohmann::json::parse(viewer_json(data));
    EXPECT_EQ(j["precision"], "double");
    EXPECT_EQ(j["families"][0]["arm"], 2);
    const auto& jo = j["families"][0]["orbits"][0];
    EXPECT_EQ(jo["energy"].get<double>(), 4.0);
    EXPECT_EQ(jo["period"].get<double>(), o.period);
    EXPECT_EQ(jo["multiplier"].get<double>(), o.multiplier);
    ASSERT_EQ(jo["theta1"].size(), 41u);
    EXPECT_EQ(jo["theta2"][40].get<double>(), o.path[40][1]);
    EXPECT_EQ(j["potential"]["values"].size(), 169u);
    EXPECT_EQ(j["potential"]["values"][60].get<double>(), g.values[60]);
    EXPECT_EQ(j["parameters"]["L2"].get<double>(), 1.0);
}

TEST(SaddleViewer, QuadNumbersKeepEveryDigit) {
    viewer_data<quad> d;
    d.maximum_energy = quad(1) / 3;
    viewer_family<quad> f;
    f.stop_reason = "stopped at </script> <!--";
    d.families.push_back(f);
    const std::string text = viewer_json(d);
    const nlohmann::json j = nlohmann::json::parse(text);
    EXPECT_EQ(j["precision"], "quad");
    EXPECT_EQ(j["families"][0]["stop_reason"], "stopped at </script> <!--");
    // 1/3 with the 36 digits of quad: read back in quad, the same number (a double's 17 digits
    // would be 1e-17 away)
    const std::string key = "\"maximum_energy\":";
    const std::size_t at = text.find(key) + key.size();
    const std::string number = text.substr(at, text.find(',', at) - at);
    EXPECT_EQ(parse_real<quad>(number, "maximum_energy"), quad(1) / 3) << number;
    EXPECT_GE(number.size(), 38u) << number;
    // the page: the data embedded with '<' escaped, so the only "</script>" are the page's own
    const std::string page = viewer_page(text, "a <title> & \"more\"");
    EXPECT_NE(page.find("<title>a &lt;title&gt; &amp; &quot;more&quot;</title>"),
              std::string::npos);
    EXPECT_NE(page.find("stopped at \\u003c/script> \\u003c!--"), std::string::npos);
    std::size_t closes = 0;
    for (std::size_t pos = page.find("</script>"); pos != std::string::npos;
         pos = page.find("</script>", pos + 1))
        ++closes;
    EXPECT_EQ(closes, 2u);
    // self-contained: nothing loaded from elsewhere (the SVG namespace name is not fetched)
    EXPECT_EQ(page.find("https:"), std::string::npos);
    EXPECT_EQ(page.find(" src="), std::string::npos);
    EXPECT_EQ(page.find("<link"), std::string::npos);
    std::size_t http = 0;
    for (std::size_t pos = page.find("http:"); pos != std::string::npos;
         pos = page.find("http:", pos + 1)) {
        EXPECT_EQ(page.compare(pos, 26, "http://www.w3.org/2000/svg"), 0);
        ++http;
    }
    EXPECT_EQ(http, 1u);
}

}  // namespace
}  // namespace flipflux::test
