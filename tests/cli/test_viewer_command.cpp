// flipflux viewer through its executable: the page written (a pendulum given by the model
// options), and bad input refused in one line with status 2 and no file.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) {
    const fs::path d = fs::path(::testing::TempDir()) /
                       ("flipflux_viewer_" + name + "_" + std::to_string(getpid()));
    fs::remove_all(d);
    return d;
}

nlohmann::json embedded_data(const std::string& page) {
    const std::string open = "<script type=\"application/json\" id=\"viewer-data\">";
    const std::size_t from = page.find(open);
    if (from == std::string::npos) return nullptr;
    const std::size_t begin = from + open.size(), end = page.find("</script>", begin);
    return nlohmann::json::parse(page.substr(begin, end - begin));
}

TEST(ViewerCommand, WritesOnePageWithTheFamilyOfTheGivenPendulum) {
    const fs::path out = fresh("page");
    // arm 2 of a pendulum with m2 = 1/2: alpha = 3/2, beta = 1/2, E_s = 1, E_max = 4: E = 2.5
    const auto r = run_flipflux(
        "viewer --out " + out.string() +
        " --arms 2 --energies 1 --samples 12 --grid 13 --m2 0.5 --integrator gauss-legendre");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string page = read_text(out / "viewer.html");
    EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
    const nlohmann::json data = embedded_data(page);
    ASSERT_TRUE(data.is_object());
    EXPECT_EQ(data["parameters"]["m2"].get<double>(), 0.5);
    EXPECT_EQ(data["maximum_energy"].get<double>(), 4.0);
    ASSERT_EQ(data["families"].size(), 1u);
    const auto& orbit = data["families"][0]["orbits"][0];
    EXPECT_EQ(orbit["energy"].get<double>(), 2.5);
    EXPECT_EQ(orbit["theta1"].size(), 12u);
    EXPECT_GT(orbit["period"].get<double>(), 0);
    EXPECT_EQ(data["potential"]["values"].size(), 169u);
    fs::remove_all(out);
}

TEST(ViewerCommand, BadInputIsOneLineStatusTwoAndNoFile) {
    const fs::path out = fresh("bad");
    const std::string base = "viewer --out " + out.string() + " ";
    const std::pair<std::string, std::string> cases[] = {
        {"--energies 0", "--energies: '0' is not an integer in [1, 1000]"},
        {"--energies x", "--energies: 'x' is not an integer"},
        {"--grid 10", "--grid: '10' is not 1 more than a multiple of 6"},
        {"--samples 3", "--samples: '3' is not an integer in [8, 100000]"},
        {"--arms 1,3", "--arms: '3' is not an arm"},
        {"--arms 2,2", "--arms: arm 2 is given twice"},
        {"--m1 0", "--m1"},
        {"--precision mp:x", "--precision"},
        {"--integrator rk4", "--integrator"},
    };
    for (const auto& [args, message] : cases) {
        const auto r = run_flipflux(base + args);
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out / "viewer.html")) << args;
    }
    // an output folder that cannot be created: a file stands where it should be
    fs::create_directories(out);
    { std::ofstream(out / "file") << "x"; }
    const auto r = run_flipflux("viewer --out " + (out / "file").string() + " --energies 1");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--out: "), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    fs::remove_all(out);
}

}  // namespace
}  // namespace flipflux::test
