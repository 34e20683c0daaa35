// Fuzz target: arbitrary bytes as a coupling frame, through the decoder (coupler/messages.hpp) for every
// message kind a side waits for, then every check of both sides on whatever body the bytes hold, and the
// quoting of a peer's text; and the bytes read as the values of well-formed messages of every kind. A bad
// frame must end in CouplingError (a message naming the peer, the step and the cause); any other exception
// escaping, a crash, a sanitizer report, a leak or a slow input is a finding.
#include "coupler/messages.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
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

// The bytes read as the values of messages: doubles, counts and texts, so that the checks also see arbitrary
// values in well-formed messages (a byte-level mutation seldom keeps protobuf's length prefixes consistent).
class Values {
  public:
    Values(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
    double real() {
        double v = 0;
        if (n_ >= sizeof v) std::memcpy(&v, p_, sizeof v), p_ += sizeof v, n_ -= sizeof v;
        return v;
    }
    int count() { return n_ ? (--n_, *p_++ % 4) : 0; } // 0 to 3 interface nodes
    std::string text() {
        const std::size_t k = n_ ? std::min<std::size_t>(*p_ * 16, n_ - 1) : 0;
        std::string t(reinterpret_cast<const char*>(p_ + (n_ ? 1 : 0)), k);
        p_ += n_ ? k + 1 : 0, n_ -= n_ ? k + 1 : 0;
        return t;
    }
    template <class R> void fill(R* r, int k) {
        for (int i = 0; i < k; ++i)
            r->Add(real());
    }

  private:
    const std::uint8_t* p_;
    std::size_t n_;
};

void check_values(const std::uint8_t* data, std::size_t size) {
    Values v(data, size);
    Envelope e;
    e.set_protocol(protocol_version);
    e.set_step(3);
    auto h = e.mutable_hello(); // each body in turn replaces the last (a oneof)
    h->set_solver(v.text()), h->set_version(v.text()), h->set_dimension(1), h->set_alpha(0);
    const int n = v.count();
    v.fill(h->mutable_x(), n), v.fill(h->mutable_y(), n), v.fill(h->mutable_normal_x(), n);
    v.fill(h->mutable_normal_y(), n), v.fill(h->mutable_area(), n);
    check_all(e);
    auto w = e.mutable_welcome();
    w->set_solver(v.text()), w->set_version(v.text()), w->set_end_time(v.real());
    check_all(e);
    auto o = e.mutable_offer();
    o->set_dt(v.real()), v.fill(o->mutable_x(), n), v.fill(o->mutable_y(), n),
        v.fill(o->mutable_velocity(), n);
    check_all(e);
    auto g = e.mutable_grant();
    g->set_dt(v.real()), g->set_time(v.real()), g->set_p_floor(v.real()), g->set_output(v.count() % 2);
    v.fill(g->mutable_p_l(), n), v.fill(g->mutable_u_l(), n), v.fill(g->mutable_z_l(), n);
    v.fill(g->mutable_geometric(), n);
    check_all(e);
    auto a = e.mutable_answer();
    v.fill(a->mutable_p_i(), n), v.fill(a->mutable_u_i(), n), v.fill(a->mutable_x(), n),
        v.fill(a->mutable_y(), n);
    check_all(e);
    e.mutable_stop()->set_reason(v.text());
    check_all(e);
    e.mutable_error()->set_message(v.text());
    const std::string bytes = e.SerializeAsString();
    refused_or_passed([&] { decode(bytes.data(), bytes.size(), peer, 3, Envelope::kGrant); });
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
    check_values(data, size);
    return 0;
}
