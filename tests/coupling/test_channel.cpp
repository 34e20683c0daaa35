// Socket-level tests of the coupling transport (coupler/channel.hpp) over real ipc:// and tcp:// sockets:
// a handshake round trip, and the failures that must end a run with a clear message naming the peer, the
// step and the cause — a silent peer (timeout), garbage bytes, another protocol version, a message out of
// order, an error reported by the peer, an endpoint already in use.
#include "coupler/channel.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>
#include <unistd.h>

using namespace undex::coupling;

namespace {

std::string endpoint(const std::string& tag) {
    return "ipc://" +
           (std::filesystem::temp_directory_path() / ("undex-test-" + std::to_string(::getpid()) + "-" + tag))
               .string();
}

Envelope hello(std::int64_t step = 0) {
    Envelope e;
    e.set_step(step);
    auto* h = e.mutable_hello();
    h->set_solver("test-structure");
    h->set_version("1");
    h->set_dimension(1);
    h->set_alpha(0);
    h->add_x(0.5);
    h->add_y(0);
    h->add_normal_x(-1);
    h->add_normal_y(0);
    h->add_area(1);
    return e;
}

// The message of the CouplingError thrown by f, or "" when none is thrown.
template <class F> std::string error_of(F f) {
    try {
        f();
    } catch (const CouplingError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(Channel, HandshakeRoundTripOverIpcAndTcp) {
    for (const std::string& where : {endpoint("roundtrip"), std::string("tcp://127.0.0.1:*")}) {
        Channel fluid(where, Channel::Role::Bind, "the structure", 5000);
        const std::string ep = fluid.endpoint();
        std::thread structure([&] {
            Channel s(ep, Channel::Role::Connect, "the fluid", 5000);
            Envelope h = hello();
            s.send(h);
            const Envelope w = s.receive(0, Envelope::kWelcome);
            EXPECT_EQ(w.welcome().solver(), "test-fluid");
            EXPECT_DOUBLE_EQ(w.welcome().end_time(), 1e-3);
        });
        const Envelope h = fluid.receive(0, Envelope::kHello);
        EXPECT_EQ(h.hello().solver(), "test-structure");
        EXPECT_EQ(h.hello().x_size(), 1);
        Envelope w;
        w.set_step(0);
        w.mutable_welcome()->set_solver("test-fluid");
        w.mutable_welcome()->set_version("1");
        w.mutable_welcome()->set_end_time(1e-3);
        fluid.send(w);
        structure.join();
    }
}

// A peer that stops answering: the wait ends after the timeout (0.3 s here; bound 2 s) with the peer, the
// step and the awaited message named. Heartbeats renew the wait.
TEST(Channel, SilentPeerTimesOutAndHeartbeatsKeepItAlive) {
    const std::string ep = endpoint("silent");
    Channel fluid(ep, Channel::Role::Bind, "the structure", 300);
    Channel structure(ep, Channel::Role::Connect, "the fluid", 300);
    const auto start = std::chrono::steady_clock::now();
    const std::string what = error_of([&] { fluid.receive(7, Envelope::kOffer); });
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_NE(what.find("the structure did not answer within 0.3"), std::string::npos) << what;
    EXPECT_NE(what.find("at step 7"), std::string::npos) << what;
    EXPECT_NE(what.find("waiting for Offer"), std::string::npos) << what;
    EXPECT_GE(waited, 0.29);
    EXPECT_LT(waited, 2.0);
    // Four heartbeats 0.2 s apart (0.8 s in all) and then the offer: no timeout.
    std::thread busy([&] {
        for (int k = 0; k < 4; ++k) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            Envelope hb;
            hb.set_step(8);
            hb.mutable_heartbeat();
            structure.send(hb);
        }
        Envelope offer;
        offer.set_step(8);
        offer.mutable_offer()->set_dt(1e-7);
        structure.send(offer);
    });
    EXPECT_DOUBLE_EQ(fluid.receive(8, Envelope::kOffer).offer().dt(), 1e-7);
    busy.join();
}

TEST(Channel, GarbageWrongVersionOutOfOrderAndPeerErrorsAreNamed) {
    const std::string ep = endpoint("bad");
    Channel fluid(ep, Channel::Role::Bind, "the structure", 2000);
    // Garbage bytes on a raw socket.
    zmq::context_t ctx;
    zmq::socket_t raw(ctx, zmq::socket_type::pair);
    raw.set(zmq::sockopt::linger, 0);
    raw.connect(ep);
    raw.send(zmq::str_buffer("\xff\xfe garbage"), zmq::send_flags::none);
    std::string what = error_of([&] { fluid.receive(0, Envelope::kHello); });
    EXPECT_NE(what.find("the structure sent a malformed message at step 0"), std::string::npos) << what;
    // Another protocol version.
    Envelope h = hello();
    h.set_protocol(99);
    raw.send(zmq::buffer(h.SerializeAsString()), zmq::send_flags::none);
    what = error_of([&] { fluid.receive(0, Envelope::kHello); });
    EXPECT_NE(what.find("speaks protocol version 99, this side version 1"), std::string::npos) << what;
    // A message of the wrong kind, then of the wrong step.
    h.set_protocol(protocol_version);
    raw.send(zmq::buffer(h.SerializeAsString()), zmq::send_flags::none);
    what = error_of([&] { fluid.receive(3, Envelope::kAnswer); });
    EXPECT_NE(what.find("sent Hello of step 0 where Answer of step 3 was expected"), std::string::npos)
        << what;
    Envelope a;
    a.set_protocol(protocol_version);
    a.set_step(2);
    a.mutable_answer();
    raw.send(zmq::buffer(a.SerializeAsString()), zmq::send_flags::none);
    what = error_of([&] { fluid.receive(3, Envelope::kAnswer); });
    EXPECT_NE(what.find("sent Answer of step 2 where Answer of step 3 was expected"), std::string::npos)
        << what;
    // An error reported by the peer ends the wait with its message.
    Envelope err;
    err.set_protocol(protocol_version);
    err.set_step(4);
    err.mutable_error()->set_message("element 12 inverted at t = 1e-4 s");
    raw.send(zmq::buffer(err.SerializeAsString()), zmq::send_flags::none);
    what = error_of([&] { fluid.receive(4, Envelope::kAnswer); });
    EXPECT_NE(what.find("the structure stopped with an error at step 4: element 12 inverted"),
              std::string::npos)
        << what;
}

TEST(Channel, EndpointAlreadyInUseIsRefused) {
    const std::string ep = endpoint("busy");
    Channel first(ep, Channel::Role::Bind, "the structure", 1000);
    std::string what = error_of([&] { Channel second(ep, Channel::Role::Bind, "the structure", 1000); });
    EXPECT_NE(what.find("endpoint " + ep + " is already in use"), std::string::npos) << what;
    Channel tcp("tcp://127.0.0.1:*", Channel::Role::Bind, "the structure", 1000);
    what = error_of([&] { Channel again(tcp.endpoint(), Channel::Role::Bind, "the structure", 1000); });
    EXPECT_NE(what.find("cannot bind endpoint " + tcp.endpoint()), std::string::npos) << what;
}
