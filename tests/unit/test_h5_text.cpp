// The output file (base/h5.hpp): the case text and the status hold any length, and a status longer than the
// space reserved for it replaces the old one whole; the write hook between datasets; a table's flushed rows
// stay readable in the file on disk while longer tables are written after the flush (a killed run).
#include "base/h5.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

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

// A run killed between two flushes leaves its file as the last flush left it, plus whatever data the writes
// since put on disk. Here the file on disk is copied (what a SIGKILL leaves) after every dataset written, by
// the write hook, through rounds of a solver's output: three tables grown by a few hundred rows, one flush
// in the middle (solid/rigid.cpp). Each copy must read back, for every column of every table, rows of the
// table: a prefix, bitwise. (Deleting and writing each column anew fails this: a new column lands in the
// space of the old ones, which the flushed state still points at.)
TEST(H5Text, TablesOfTheLastFlushSurviveAKill) {
    const auto dir = std::filesystem::temp_directory_path() / ("undex-h5-kill-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    struct Table {
        std::string group;
        std::vector<std::string> columns;
        std::vector<double> rows; // each value unique
    };
    std::vector<Table> tables{{"gauges/plate", {"t", "u", "v", "p_I"}, {}},
                              {"coupling", {"t", "dt", "p_I", "u_I", "dt_s"}, {}},
                              {"energies", {"t", "external"}, {}}};
    std::vector<std::filesystem::path> copies;
    {
        undex::h5::OutputFile out(dir.string(), "test.h5", "case");
        undex::h5::create_group(out.id(), "gauges").close();
        const undex::h5::WriteHook copy(
            [&] {
                copies.push_back(dir / ("copy" + std::to_string(copies.size()) + ".h5"));
                std::filesystem::copy_file(out.path(), copies.back());
            },
            0.0);
        for (int round = 0; round < 6; ++round) {
            for (size_t n = 0; n < tables.size(); ++n) {
                Table& tab = tables[n];
                for (int r = 0; r < 300; ++r)
                    for (size_t k = 0; k < tab.columns.size(); ++k)
                        tab.rows.push_back(1e6 * static_cast<double>(n + 1) + static_cast<double>(tab.rows.size()));
                if (tab.group == "coupling")
                    out.write_table(tab.group, tab.columns, tab.rows); // flushes
                else
                    undex::h5::write_table(out.id(), tab.group, tab.columns, tab.rows);
            }
        }
        out.complete();
    }
    ASSERT_EQ(copies.size(), 6u * 11u);
    size_t read = 0;
    for (const auto& path : copies) {
        const auto f = undex::h5::open_read(path.string());
        for (const Table& tab : tables) {
            if (H5Lexists(f.id(), tab.group.c_str(), H5P_DEFAULT) <= 0) continue; // not flushed yet
            const auto g = undex::h5::open_group(f.id(), tab.group);
            for (size_t k = 0; k < tab.columns.size(); ++k) {
                if (H5Lexists(g.id(), tab.columns[k].c_str(), H5P_DEFAULT) <= 0) continue;
                const std::vector<double> v = undex::h5::read_dataset(g.id(), tab.columns[k]);
                const size_t width = tab.columns.size();
                ASSERT_LE(v.size() * width, tab.rows.size());
                for (size_t r = 0; r < v.size(); ++r)
                    ASSERT_EQ(std::memcmp(&v[r], &tab.rows[r * width + k], sizeof(double)), 0)
                        << path << ": " << tab.group << "/" << tab.columns[k] << " row " << r << " reads " << v[r]
                        << ", written " << tab.rows[r * width + k];
                ++read;
            }
        }
    }
    EXPECT_GT(read, 5u * 11u * 5u); // most copies hold most columns
    std::filesystem::remove_all(dir);
}

} // namespace
