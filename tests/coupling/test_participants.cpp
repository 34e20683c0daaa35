// The coupling library's two sides over a real ipc:// socket: the grant is Δt = min(Δt_f, Δt_s) whichever
// side is the smaller, and both sides see the same step and time (docs/protocol.md).
#include "coupler/participant.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <thread>
#include <unistd.h>

using namespace undex::coupling;

// Two steps: the structure offers 1e-8 s, and the fluid asks for 1e-7 s (the structure's step is granted),
// then 4e-9 s (the fluid's is). The structure's side must receive exactly the granted steps and times.
TEST(Participants, TheGrantIsTheSmallerOfBothSteps) {
    Options o;
    o.endpoint = "ipc://" + (std::filesystem::temp_directory_path() /
                             ("undex-test-" + std::to_string(::getpid()) + "-participants"))
                                .string();
    o.timeout_ms = 10000;
    o.handshake_timeout_ms = 10000;
    const double dt_s = 1e-8, end_time = 1.0;
    std::vector<double> granted_to_structure, times_at_structure;
    std::thread structure([&] {
        StructureParticipant s(o, "test-structure", "1");
        Interface i;
        i.x = {0.5}, i.y = {0}, i.normal_x = {1}, i.normal_y = {0}, i.area = {1};
        s.initialize(i);
        Offer offer;
        offer.dt = dt_s, offer.x = {0.5}, offer.y = {0}, offer.velocity = {0};
        Grant g;
        while (s.exchange(offer, g)) {
            granted_to_structure.push_back(g.dt);
            times_at_structure.push_back(g.time);
            s.answer(Answer{{1e5}, {0}, {0.5}, {0}});
        }
    });
    FluidParticipant f(o, "test-fluid", "1");
    f.initialize(1, 0, end_time);
    std::vector<double> granted;
    double t = 0;
    for (const double dt_f : {1e-7, 4e-9}) {
        Offer offer;
        ASSERT_TRUE(f.receive_offer(offer));
        EXPECT_EQ(offer.dt, dt_s);
        Grant g;
        g.time = t, g.p_floor = 0, g.p_L = {1e5}, g.u_L = {0}, g.Z_L = {1.5e6}, g.geometric = {0};
        f.exchange(dt_f, g);
        granted.push_back(g.dt);
        t += g.dt;
    }
    f.finalize("test done"); // takes the third offer and answers it with Stop
    structure.join();
    EXPECT_EQ(granted, (std::vector<double>{1e-8, 4e-9}));
    EXPECT_EQ(granted_to_structure, granted);
    EXPECT_EQ(times_at_structure, (std::vector<double>{0.0, 1e-8}));
}
