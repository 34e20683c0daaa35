// Checkpoints (base/checkpoint.hpp): what State writes reads back bit for bit, a missing piece and a
// checkpoint of the other side are refused by name, and which files a side keeps: always a pair at one step
// for resume_pair, however the two sides' writes fall, and at most two per side.
#include "base/checkpoint.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Dir {
    fs::path path;
    explicit Dir(const std::string& name) : path(fs::temp_directory_path() / ("undex_test_" + name)) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~Dir() { fs::remove_all(path); }
};

std::set<long> steps_of(const Dir& d, const std::string& side) {
    std::set<long> s;
    for (const auto& c : undex::checkpoints(d.path.string(), side))
        s.insert(c.first);
    return s;
}

void write(const Dir& d, const std::string& side, const std::string& partner, long step) {
    undex::State s = undex::State::create(d.path.string(), side, partner, step, 1e-6 * step, "case");
    long n = step;
    s.io("n", n);
    s.commit();
}

struct Point {
    double a[3];
    int k;
};

TEST(Checkpoint, WhatIsWrittenReadsBackBitForBit) {
    const Dir d("checkpoint_roundtrip");
    std::vector<double> u = {1.0 / 3, -0.0, std::numeric_limits<double>::denorm_min(), 1e308};
    std::vector<char> mask = {0, 1, 1, 0, 1};
    std::vector<Point> points = {{{1, 2, 3}, 4}, {{-5, 6.5, 7e-300}, -8}};
    std::vector<long> empty;
    double t = 2.5e-4;
    bool flag = true;
    undex::State w = undex::State::create(d.path.string(), "fluid", "", 7, t, "name: \"x\"\n");
    undex::State inner = w.scope("solver").scope("side0");
    inner.io("u", u), inner.io("mask", mask), w.io("points", points), w.io("empty", empty);
    w.io("t", t), w.io("flag", flag);
    const std::string path = w.commit();
    EXPECT_EQ(path, (d.path / "fluid.checkpoint.000000007.h5").string());

    undex::State r = undex::State::open(path, "fluid");
    EXPECT_TRUE(r.loading());
    EXPECT_EQ(r.step(), 7);
    EXPECT_EQ(r.time(), 2.5e-4);
    EXPECT_EQ(r.case_text(), "name: \"x\"\n");
    std::vector<double> u2;
    std::vector<char> mask2;
    std::vector<Point> points2;
    std::vector<long> empty2 = {1, 2};
    double t2 = 0;
    bool flag2 = false;
    undex::State rin = r.scope("solver").scope("side0");
    rin.io("u", u2), rin.io("mask", mask2), r.io("points", points2), r.io("empty", empty2);
    r.io("t", t2), r.io("flag", flag2);
    ASSERT_EQ(u2.size(), u.size());
    for (size_t k = 0; k < u.size(); ++k) {
        EXPECT_EQ(std::signbit(u2[k]), std::signbit(u[k]));
        EXPECT_EQ(u2[k], u[k]);
    }
    EXPECT_EQ(mask2, mask);
    ASSERT_EQ(points2.size(), 2u);
    EXPECT_EQ(points2[1].a[2], 7e-300);
    EXPECT_EQ(points2[1].k, -8);
    EXPECT_TRUE(empty2.empty());
    EXPECT_EQ(t2, t);
    EXPECT_TRUE(flag2);

    std::vector<double> missing;
    try {
        r.io("solver.side1.u", missing);
        FAIL() << "a piece the checkpoint lacks was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("holds no solver.side1.u"), std::string::npos) << e.what();
    }
    try {
        undex::State::open(path, "solid");
        FAIL() << "the fluid's checkpoint was taken for the structure's";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("of the fluid side, not of the solid"), std::string::npos)
            << e.what();
    }
}

TEST(Checkpoint, AlwaysKeepsAPairAtOneStep) {
    const Dir d("checkpoint_pairs");
    const std::string dir = d.path.string();
    write(d, "fluid", "solid", 10), write(d, "solid", "fluid", 10);
    EXPECT_EQ(undex::resume_pair(dir).first, (d.path / "fluid.checkpoint.000000010.h5").string());
    // The structure cannot write (a full disk): the fluid goes on, keeping the step both hold.
    write(d, "fluid", "solid", 20);
    write(d, "fluid", "solid", 30);
    EXPECT_EQ(steps_of(d, "fluid"), (std::set<long>{10, 30}));
    EXPECT_EQ(undex::resume_pair(dir).second, (d.path / "solid.checkpoint.000000010.h5").string());
    // Both write again: the pair moves to 30, then the older files go.
    write(d, "solid", "fluid", 30);
    EXPECT_EQ(undex::resume_pair(dir).first, (d.path / "fluid.checkpoint.000000030.h5").string());
    write(d, "fluid", "solid", 40), write(d, "solid", "fluid", 40);
    EXPECT_EQ(steps_of(d, "fluid"), (std::set<long>{30, 40}));
    EXPECT_EQ(steps_of(d, "solid"), (std::set<long>{30, 40}));
    EXPECT_EQ(undex::resume_pair(dir).second, (d.path / "solid.checkpoint.000000040.h5").string());
    // A side alone keeps its newest two.
    write(d, "alone", "", 1), write(d, "alone", "", 2), write(d, "alone", "", 3);
    EXPECT_EQ(steps_of(d, "alone"), (std::set<long>{2, 3}));
    EXPECT_EQ(undex::resume_single(dir, "alone"), (d.path / "alone.checkpoint.000000003.h5").string());
    undex::remove_checkpoints(dir, "alone");
    EXPECT_TRUE(steps_of(d, "alone").empty());
    EXPECT_THROW(undex::resume_single(dir, "alone"), std::runtime_error);
}

TEST(Checkpoint, NoPairIsRefusedNamingWhatThereIs) {
    const Dir d("checkpoint_no_pair");
    write(d, "fluid", "solid", 5), write(d, "solid", "fluid", 6);
    try {
        undex::resume_pair(d.path.string());
        FAIL() << "a fluid at step 5 and a structure at 6 were resumed together";
    } catch (const std::runtime_error& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("at the same step"), std::string::npos) << w;
        EXPECT_NE(w.find("fluid.checkpoint.000000005.h5: step 5"), std::string::npos) << w;
        EXPECT_NE(w.find("solid.checkpoint.000000006.h5: step 6"), std::string::npos) << w;
    }
}

} // namespace
