// The fluid's MPI ranks (started by mpirun; docs/scale_out.md). The 2D mesh is divided into blocks of whole
// rows, one per rank: a rank solves the cells of its rows and keeps the `halo` rows on either side as its
// neighbours computed them. Every rank holds arrays of the whole padded mesh (rows stay contiguous, so a
// block of rows is one contiguous range and is sent without packing); rows outside the rank's block and its
// halo are stale until share() makes the whole state current on every rank (before an output and a new
// division). Without mpirun there is one rank and every call is a no-op. MPI stays inside ranks.cpp.
#pragma once
#include <memory>
#include <string>
#include <vector>

namespace undex::fluid {

class Ranks {
  public:
    // The ranks of this process: MPI_COMM_WORLD when started by mpirun (MPI initialised on first use and
    // finalised at exit), one rank otherwise.
    static Ranks& world();
    int rank() const { return rank_; }
    int size() const { return size_; }
    bool many() const { return size_ > 1; }
    bool root() const { return rank_ == 0; }

    // The division of ny rows: rank r solves rows [first[r], first[r + 1]). Balanced by cost (one entry per
    // row, the cells it updates): each block's cost as near the mean as whole rows allow, at least `min_rows`
    // rows per block. Throws std::invalid_argument when ny < size · min_rows.
    void divide(const std::vector<double>& cost, int min_rows);
    int begin() const { return first_[rank_]; }
    int end() const { return first_[rank_ + 1]; }
    int begin(int r) const { return first_[r]; }
    int end(int r) const { return first_[r + 1]; }
    // max over the blocks of their cost / mean cost (1: balanced).
    double imbalance(const std::vector<double>& cost) const;

    // Halo exchange on an array of padded rows (padded row r = j + 1, `row` doubles or bytes each): the first
    // and last `depth` rows of this rank's block go to the neighbours, theirs come into the rows beyond it.
    void exchange(double* rows, long row, int depth) const;
    void exchange(char* rows, long row, int depth) const;
    // Several at once, one wait for all (the same list, in the same order, on every rank).
    struct Rows {
        double* rows;
        long row;
        int depth;
    };
    void exchange(const std::vector<Rows>& x) const;
    // The same in two halves: post() starts the messages, complete() waits for them. Between the two the
    // rows sent must not change and the rows received must be neither read nor written.
    // progress(), called now and then between them (from the thread that called post), lets the messages
    // advance while this rank computes: a message of many rows is copied only when its receiver asks for it,
    // so that without it a rank's send would wait for the neighbour to reach its own complete().
    void post(const std::vector<Rows>& x) const;
    void progress() const;
    void complete() const;
    // Every rank's block to every rank (padded rows as exchange()).
    void share(double* rows, long row) const;
    void share(char* rows, long row) const;

    // In place, over the ranks: the element-wise maximum (exact and the same on every rank whatever the
    // order), the sum of integers.
    void max(std::vector<double>& v) const;
    long sum(long v) const;
    // Rank `from`'s text, or numbers, on every rank.
    std::string broadcast(const std::string& text, int from) const;
    std::vector<double> broadcast(const std::vector<double>& v, int from) const;
    // Gathers variable-length data to the root (rank order); other ranks get {}.
    std::vector<double> gather(const std::vector<double>& v) const;
    // Every rank's `mine` into `out` on every rank, in rank order; count[r]: the length of rank r's (known
    // to all).
    void gather_all(const std::vector<double>& mine, const std::vector<int>& count,
                    std::vector<double>& out) const;

    // A rank left waiting on the others (one hangs, or died unnoticed): from now on, once one exchange or
    // reduction has waited `seconds`, this rank says what it waits on and in which step (at_step) on stderr
    // and ends with exit status 3, and mpirun ends the others (0: wait for ever). Also when `stopped()`
    // turns true during a wait (a signal: mpirun ending the job after a rank died), with status 4. A
    // thread of its own watches.
    void watch(double seconds, bool (*stopped)() = nullptr) const;
    void at_step(long step) const;
    // Seconds this rank has waited in all in the halo exchanges, the reductions, the broadcasts and the
    // gathers (and shares of the state), in that order: its idle time, for the run's summary.
    static constexpr int wait_kinds = 4;
    std::vector<double> waits() const;

    // Ends every rank at once (MPI_Abort), after `why` on stderr: for a rank that cannot go on alone.
    [[noreturn]] void abort(const std::string& why, int status) const;

  private:
    Ranks() = default;
    int rank_ = 0, size_ = 1;
    std::vector<int> first_ = {0, 0};
    struct Pending; // the messages post() started
    mutable std::shared_ptr<Pending> pending_;
    template <class T> void exchange_rows(T* rows, long row, int depth) const;
    template <class T> void post_rows(T* rows, long row, int depth, void* requests) const;
    template <class T> void share_rows(T* rows, long row) const;
};

} // namespace undex::fluid
