// The output file (base/h5.hpp): the case text and the status hold any length, and a status longer than the
// space reserved for it replaces the old one whole; the write hook between datasets.
#include "base/h5.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

namespace {

std::string status_of(const undex::h5::OutputFile& out) {
    return undex::h5::read_text(out.id(), "status");
}

TEST(H5Text, CaseAndStatusOfAnyLength) {
    const auto dir = std::filesystem::temp_directory_path() / ("undex-h5-text-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    const std::string long_case(200000, 'c'); // over HDF5's 64 KiB limit of an attribute
    std::string path;
    {
        undex::h5::OutputFile out(dir.string(), "test.h5", long_case);
        path = out.path();
        EXPECT_EQ(status_of(out), "running");
        const std::string long_status = "failed: " + std::string(10000, 's'); // over the 4096 bytes reserved
        out.set_status(long_status);
        EXPECT_EQ(status_of(out), long_status);
        out.set_status("failed: short"); // in place, the rest of the dataset padded
        EXPECT_EQ(status_of(out), "failed: short");
        out.complete();
    }
    const auto file = undex::h5::open_read(path);
    EXPECT_EQ(undex::h5::read_text(file.id(), "case"), long_case);
    EXPECT_EQ(undex::h5::read_text(file.id(), "status"), "complete");
    std::filesystem::remove_all(dir);
}

// A WriteHook runs after a dataset is written, at most once per its period, and only while in scope: what
// keeps a coupling partner waiting through a long output.
TEST(H5Text, WriteHookBetweenDatasets) {
    const auto dir = std::filesystem::temp_directory_path() / ("undex-h5-hook-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    {
        undex::h5::OutputFile out(dir.string(), "test.h5", "case");
        const double x[3] = {1, 2, 3};
        int calls = 0;
        {
            const undex::h5::WriteHook every(([&] { ++calls; }), 0.0);
            undex::h5::write_dataset(out.id(), "a", {3}, x);
            undex::h5::write_dataset(out.id(), "b", {3}, x);
            out.write_table("table", {"t", "p"}, {0, 1, 2, 3});
        }
        EXPECT_EQ(calls, 4); // two datasets and the table's two columns
        {
            const undex::h5::WriteHook rarely(([&] { ++calls; }), 3600.0);
            undex::h5::write_dataset(out.id(), "c", {3}, x);
        }
        EXPECT_EQ(calls, 4); // not within the hour after it was set
        undex::h5::write_dataset(out.id(), "d", {3}, x);
        EXPECT_EQ(calls, 4); // none in scope
        out.complete();
    }
    std::filesystem::remove_all(dir);
}

} // namespace
