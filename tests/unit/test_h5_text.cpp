// The text datasets of an output file (base/h5.hpp): the case text and the status hold any length, and a
// status longer than the space reserved for it replaces the old one whole.
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

} // namespace
