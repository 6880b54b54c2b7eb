// Bad input names its field, not a command-line option (core/error.hpp): the library's messages
// are "field: detail"; the CLI turns the field into its option (tests/cli: RefusesBadInput), a
// scene into its file, line and key.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

input_error caught(const std::function<void()>& f) {
    try {
        f();
    } catch (const input_error& e) {
        return e;
    }
    ADD_FAILURE() << "no input_error";
    return input_error("");
}

TEST(InputError, AboutAFieldKeepsFieldAndDetail) {
    const input_error e = input_error::about("sample_interval", "'1' needs a CSV directory");
    EXPECT_STREQ(e.what(), "sample_interval: '1' needs a CSV directory");
    EXPECT_EQ(e.field(), "sample_interval");
    EXPECT_EQ(e.detail(), "'1' needs a CSV directory");
    const input_error free("golden csv: line 3: bad");
    EXPECT_EQ(free.field(), "");
}

TEST(InputError, LibraryErrorsNameFieldsNotOptions) {
    struct expectation {
        std::function<void()> f;
        std::string field, value;
    };
    const std::vector<expectation> cases{
        {[] { (void)parse_precision("mp:0"); }, "precision", "'mp:0'"},
        {[] { (void)parse_real<double>("1x", "energy"); }, "energy", "'1x'"},
        {[] {
             physical_parameters<double> p;
             p.m2 = -1;
             (void)double_pendulum<double>(p);
         },
         "m2", "'-1'"},
        {[] {
             ensemble_options o;
             o.energy = 5;
             o.trajectories = 0;
             validate(o);
         },
         "trajectories", "'0'"},
        {[] {
             ensemble_options o;
             o.energy = 5;
             o.trajectories = 3;
             o.time = 1;
             o.rtol = 0;
             validate(o);
         },
         "rtol", "'0'"},
    };
    for (const auto& c : cases) {
        const input_error e = caught(c.f);
        EXPECT_EQ(e.field(), c.field) << e.what();
        EXPECT_EQ(e.detail().rfind(c.value, 0), 0u) << e.what();
        EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace flipflux::test
