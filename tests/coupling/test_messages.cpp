// The coupling messages without a socket (coupler/messages.hpp): decoding, and the check of every received
// value on both sides — non-finite and out-of-range values, a Δt below the floor, a Grant.time that is not
// the structure's own, an unbounded or non-UTF-8 text of the peer. Every refusal names the field and the
// step.
#include "base/case_file.hpp"
#include "base/run_driver.hpp"
#include "base/run_plan.hpp"
#include "coupler/messages.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace undex::coupling;

namespace {

const double inf = std::numeric_limits<double>::infinity(), NaN = std::nan("");
const std::string fluid = "the fluid solver", structure = "the structure solver";

// The message of the CouplingError thrown by f, or "" when none is thrown.
template <class F> std::string error_of(F f) {
    try {
        f();
    } catch (const CouplingError& e) {
        return e.what();
    }
    return "";
}

wire::Grant grant() {
    wire::Grant g;
    g.set_dt(1e-7);
    g.set_time(2e-7);
    g.set_p_floor(2338);
    g.add_p_l(1e5), g.add_u_l(0), g.add_z_l(1.5e6), g.add_geometric(0);
    return g;
}

wire::Hello hello() {
    wire::Hello h;
    h.set_solver("s"), h.set_version("1"), h.set_dimension(1), h.set_alpha(0);
    h.add_x(0.5), h.add_y(0), h.add_normal_x(1), h.add_normal_y(0), h.add_area(1);
    return h;
}

// Grant of step 3 offered dt_s = 1e-6, the structure at t = 2e-7, end time 1e-3.
std::string grant_error(const wire::Grant& g, bool after_short = false) {
    return error_of([&] { check_grant(g, 1, 1e-6, 2e-7, 1e-3, after_short, fluid, 3); });
}

} // namespace

TEST(Messages, TheDtFloorIsTheRunDriversFloor) {
    EXPECT_EQ(limits::dt_floor_fraction, undex::dt_floor_fraction);
}

TEST(Messages, AValidGrantPassesAndEveryBadValueIsRefusedNamingFieldAndStep) {
    EXPECT_EQ(grant_error(grant()), "");
    struct Case {
        const char* field;
        void (*spoil)(wire::Grant&);
    };
    const Case cases[] = {
        {"Grant.p_floor = inf", [](wire::Grant& g) { g.set_p_floor(inf); }},
        {"Grant.p_floor = nan", [](wire::Grant& g) { g.set_p_floor(NaN); }},
        {"Grant.p_floor = 1e+20", [](wire::Grant& g) { g.set_p_floor(1e20); }},
        {"Grant.time = nan", [](wire::Grant& g) { g.set_time(NaN); }},
        {"Grant.time = 0", [](wire::Grant& g) { g.set_time(0); }}, // not the structure's 2e-7
        {"Grant.dt = nan", [](wire::Grant& g) { g.set_dt(NaN); }},
        {"Grant.dt = 5e-324", [](wire::Grant& g) { g.set_dt(5e-324); }},
        {"Grant.dt = 2e-06", [](wire::Grant& g) { g.set_dt(2e-6); }}, // above dt_s
        {"Grant.p_L at interface node 0 = -inf", [](wire::Grant& g) { g.set_p_l(0, -inf); }},
        {"Grant.u_L at interface node 0 = nan", [](wire::Grant& g) { g.set_u_l(0, NaN); }},
        {"Grant.Z_L at interface node 0 = 0", [](wire::Grant& g) { g.set_z_l(0, 0); }},
        {"Grant.geometric at interface node 0 = inf", [](wire::Grant& g) { g.set_geometric(0, inf); }},
        {"2 value(s) of Grant.p_L", [](wire::Grant& g) { g.add_p_l(1e5); }},
    };
    for (const Case& c : cases) {
        wire::Grant g = grant();
        c.spoil(g);
        const std::string what = grant_error(g);
        EXPECT_NE(what.find(c.field), std::string::npos) << c.field << ": " << what;
        EXPECT_NE(what.find("at step 3"), std::string::npos) << what;
    }
}

TEST(Messages, AStepBelowTheFloorPassesOnlyWhenItEndsOnAnOutputTime) {
    wire::Grant g = grant();
    g.set_dt(1e-16); // floor 1e-12 × 1e-3 s = 1e-15 s
    EXPECT_NE(grant_error(g), "");
    g.set_output(true);
    EXPECT_EQ(grant_error(g), "");
    EXPECT_NE(grant_error(g, true), ""); // but not two in a row: output times that close are merged
    wire::Offer o;
    o.add_x(0), o.add_y(0), o.add_velocity(0);
    for (double dt : {5e-324, 1e-16, -1.0, inf, NaN}) {
        o.set_dt(dt);
        const std::string what = error_of([&] { check_offer(o, 1, 1e-3, structure, 4); });
        EXPECT_NE(what.find("Offer.dt"), std::string::npos) << dt << ": " << what;
        EXPECT_NE(what.find("at step 4"), std::string::npos) << what;
    }
    o.set_dt(1e300); // "nothing limits my step"
    EXPECT_EQ(error_of([&] { check_offer(o, 1, 1e-3, structure, 4); }), "");
}

TEST(Messages, WelcomeEndTimeMustBePositiveAndFinite) {
    wire::Welcome w;
    w.set_solver("f"), w.set_version("1");
    std::string name;
    for (double t : {-1e-3, 0.0, NaN, inf, 1e300 * 1e300}) {
        w.set_end_time(t);
        const std::string what = error_of([&] { check_welcome(w, name); });
        EXPECT_NE(what.find("Welcome.end_time"), std::string::npos) << t << ": " << what;
        EXPECT_NE(what.find("at step 0"), std::string::npos) << what;
    }
    w.set_end_time(1e-3);
    EXPECT_DOUBLE_EQ(check_welcome(w, name), 1e-3);
    EXPECT_EQ(name, "f 1");
}

TEST(Messages, HelloAndAnswerValuesAreChecked) {
    std::string name;
    EXPECT_EQ(error_of([&] { check_hello(hello(), 1, 0, name); }), "");
    wire::Hello h = hello();
    h.set_x(0, inf);
    EXPECT_NE(error_of([&] { check_hello(h, 1, 0, name); }).find("Hello.x at interface node 0 = inf"),
              std::string::npos);
    h = hello();
    h.set_normal_x(0, 0.5);
    EXPECT_NE(error_of([&] { check_hello(h, 1, 0, name); }).find("has length 0.5"), std::string::npos);
    h = hello();
    h.set_area(0, 0);
    EXPECT_NE(error_of([&] { check_hello(h, 1, 0, name); }).find("wetted area 0"), std::string::npos);
    wire::Answer a;
    a.add_p_i(1e5), a.add_u_i(0), a.add_x(0), a.add_y(0);
    EXPECT_EQ(error_of([&] { check_answer(a, 1, 2338, structure, 5); }), "");
    a.set_p_i(0, 100);
    EXPECT_NE(error_of([&] { check_answer(a, 1, 2338, structure, 5); }).find("below the floor"),
              std::string::npos);
    a.set_p_i(0, 1e5), a.set_u_i(0, NaN);
    EXPECT_NE(error_of([&] {
                  check_answer(a, 1, 2338, structure, 5);
              }).find("Answer.u_I at interface node 0 = nan"),
              std::string::npos);
}

// A peer's text goes into our messages bounded, printable and valid UTF-8 (the status of an
// output file and the logs take it): 1 MB of Error message becomes about 1000 characters.
TEST(Messages, APeersTextIsQuotedBoundedAndPrintable) {
    EXPECT_EQ(quote("element 12 inverted"), "element 12 inverted");
    EXPECT_EQ(quote("p\xC3\xA9 \xE2\x86\x92"), "p\xC3\xA9 \xE2\x86\x92"); // é →: valid UTF-8 stays
    EXPECT_EQ(quote("a\nb\xFF\xC3"), "a\\x0Ab\\xFF\\xC3");
    EXPECT_EQ(quote("\xED\xA0\x80"), "\\xED\\xA0\\x80"); // a UTF-16 surrogate is no UTF-8
    const std::string quoted = quote(std::string(1 << 20, '\xFE'));
    EXPECT_LT(quoted.size(), 4 * limits::quoted_message + 40);
    EXPECT_NE(quoted.find("(1048576 bytes in all)"), std::string::npos);

    Envelope e;
    e.set_protocol(protocol_version);
    e.set_step(7);
    e.mutable_error()->set_message(std::string(1 << 20, 'x') + "\xFF");
    const std::string bytes = e.SerializeAsString();
    const std::string what =
        error_of([&] { decode(bytes.data(), bytes.size(), fluid, 7, Envelope::kGrant); });
    EXPECT_NE(what.find("the fluid solver stopped with an error at step 7: xxx"), std::string::npos);
    EXPECT_LT(what.size(), 1200u);
}

TEST(Messages, DecodeRefusesWhatIsNoEnvelopeOfTheStep) {
    const std::string garbage = "\xFF\x00 no envelope";
    EXPECT_NE(error_of([&] {
                  decode(garbage.data(), garbage.size(), fluid, 1, Envelope::kGrant);
              }).find("malformed message at step 1"),
              std::string::npos);
    Envelope e;
    e.set_protocol(protocol_version);
    e.set_step(2);
    *e.mutable_grant() = grant();
    const std::string bytes = e.SerializeAsString();
    EXPECT_EQ(decode(bytes.data(), bytes.size(), fluid, 2, Envelope::kGrant).grant().dt(), 1e-7);
    EXPECT_NE(error_of([&] {
                  decode(bytes.data(), bytes.size(), fluid, 3, Envelope::kGrant);
              }).find("sent Grant of step 2 where Grant of step 3 was expected"),
              std::string::npos);
}

// The run driver's side of the Δt floor (base/run_driver.hpp): a step below 1e-12 × end_time is refused
// unless it ends on an output time, and plan() merges output times closer than the floor, keeping the end.
TEST(DtFloor, TheDriverRefusesACollapsedStepAndPlanMergesCloseOutputTimes) {
    const auto c = undex::CaseFile::from_text("geometry: PLANAR_1D\nend_time: 1e-3\noutput { times: [5e-4, "
                                              "5.000000000001e-4, 9.99999999999999e-4] }\n");
    const undex::RunPlan p = undex::plan(c);
    ASSERT_EQ(p.output_times.size(), 2u); // 5e-4 + 1e-16 and end_time - 1e-18 merged
    EXPECT_EQ(p.output_times[0], 5.000000000001e-4);
    EXPECT_EQ(p.output_times[1], 1e-3);
    const undex::OutputClock clock(p, 0);
    EXPECT_EQ(clock.dt_floor(), 1e-15);
    EXPECT_FALSE(clock.admissible({5e-324, false}));
    EXPECT_FALSE(clock.admissible({9e-16, false}));
    EXPECT_TRUE(clock.admissible({9e-16, true})); // shortened to land on an output time
    EXPECT_TRUE(clock.admissible({1e-15, false}));
    EXPECT_FALSE(clock.admissible({NaN, true}));
}
