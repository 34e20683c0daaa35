// Fuzz target: arbitrary bytes as a coupling frame, through the decoder (coupler/messages.hpp) for every
// message kind a side waits for, then every check of both sides on whatever body the bytes hold, and the
// quoting of a peer's text. A bad frame must end in CouplingError (a message naming the peer, the step and
// the cause); any other exception escaping, a crash, a sanitizer report, a leak or a slow input is a finding.
#include "coupler/messages.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

using namespace undex::coupling;

namespace {

const std::string peer = "the peer";

template <class F> void refused_or_passed(F f) {
    try {
        f();
    } catch (const CouplingError&) {
    }
}

// Every check of both sides that applies to e's body, with the sizes and times the body itself suggests
// (so that the checks get past the node count) and with fixed ones.
void check_all(const Envelope& e) {
    const std::int64_t step = e.step();
    std::string name;
    if (e.has_hello()) {
        refused_or_passed([&] { check_hello(e.hello(), 1, 0, name); });
        refused_or_passed([&] { check_hello(e.hello(), e.hello().dimension(), e.hello().alpha(), name); });
    }
    if (e.has_welcome()) refused_or_passed([&] { check_welcome(e.welcome(), name); });
    if (e.has_offer())
        for (double end_time : {1e-3, e.offer().dt() * 1e6})
            refused_or_passed([&] { check_offer(e.offer(), e.offer().x_size(), end_time, peer, step); });
    if (e.has_grant()) {
        const auto& g = e.grant();
        refused_or_passed([&] { check_grant(g, 1, 1e-6, 0, 1e-3, false, peer, step); });
        refused_or_passed(
            [&] { check_grant(g, g.p_l_size(), g.dt(), g.time(), 2 * g.time() + g.dt(), true, peer, step); });
    }
    if (e.has_answer()) {
        refused_or_passed([&] { check_answer(e.answer(), 1, 2338, peer, step); });
        refused_or_passed([&] { check_answer(e.answer(), e.answer().p_i_size(), -1e300, peer, step); });
    }
    if (e.has_stop()) check_stop(e.stop());
    if (e.has_error()) quote(e.error().message());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    for (auto expected :
         {Envelope::kHello, Envelope::kWelcome, Envelope::kOffer, Envelope::kGrant, Envelope::kAnswer})
        for (std::int64_t step : {0, 1, 3})
            refused_or_passed([&] { check_all(decode(data, size, peer, step, expected)); });
    // The checks on any body the bytes hold, whatever its step or version.
    Envelope e;
    if (e.ParsePartialFromArray(data, static_cast<int>(size))) check_all(e);
    quote(std::string(reinterpret_cast<const char*>(data), size));
    quote(std::string(reinterpret_cast<const char*>(data), size), 3);
    return 0;
}
