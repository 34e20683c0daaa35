#include "fluid/ranks.hpp"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace undex::fluid {

namespace {

// MPI is initialised when the process was started by mpirun (which sets OMPI_COMM_WORLD_SIZE) and finalised
// when the process ends normally.
struct Session {
    bool on = false;
    Session() {
        if (!std::getenv("OMPI_COMM_WORLD_SIZE")) return;
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
        on = true;
    }
    ~Session() {
        int done = 0;
        if (on && (MPI_Finalized(&done), !done)) MPI_Finalize();
    }
};

// The watch over waits (Ranks::watch): when the wait under way began (steady clock, ns; 0: none), on which
// ranks (−1: all), and the step; a thread looks every 0.1 s.
struct Watch {
    std::atomic<long> since{0}, step{0};
    std::atomic<int> peer[2] = {-1, -1};
    std::atomic<const char*> what{"a halo exchange"}; // what the wait on peer is
    std::atomic<bool> done{false};
    double waited[Ranks::wait_kinds] = {}; // seconds in all, by kind (Ranks::waits)
    double limit = 0;
    bool (*stopped)() = nullptr;
    long signalled = 0; // when stopped() was first seen true
    int rank = 0, size = 1;
    std::thread thread;
    ~Watch() {
        done = true;
        if (thread.joinable()) thread.join();
    }
    static long now() {
        return std::chrono::duration_cast<std::chrono::nanoseconds>(
                   std::chrono::steady_clock::now().time_since_epoch())
            .count();
    }
    void run() {
        while (!done) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            const long s = since;
            if (s == 0) continue;
            // A signal while waiting: mpirun ending the job because another rank died, once the wait has
            // outlasted the signal by half a second (a signal to stop in order is agreed at the step's end,
            // and every rank gets there).
            if (stopped && stopped() && signalled == 0) signalled = now();
            const bool signal = signalled != 0 && s < signalled && (now() - signalled) * 1e-9 > 0.5;
            if (!signal && (now() - s) * 1e-9 < limit) continue;
            std::ostringstream m;
            m << "undex-fluid: error: fluid rank " << rank;
            if (signal)
                m << " was stopped by a signal (mpirun's, when another rank dies) while waiting ";
            else
                m << " has waited " << limit << " s ";
            const int a = peer[0], b = peer[1];
            if (a < 0 && b < 0 && size == 2)
                m << "on rank " << 1 - rank << " (a reduction over both) in step " << step;
            else if (a < 0 && b < 0)
                m << "on one of the other ranks (a reduction over all) in step " << step;
            else
                m << "on rank " << (a >= 0 ? a : b) << (a >= 0 && b >= 0 ? " or " + std::to_string(b) : "")
                  << " (" << what.load() << ") in step " << step;
            m << (signal ? "" : ": it hangs or died") << "; every rank ends";
            std::cerr << m.str() << std::endl;
            std::_Exit(signal ? 4 : 3); // exit_stopped, exit_coupling_failed: mpirun ends the others
        }
    }
};
Watch& watch_state() {
    static Watch w;
    return w;
}
// A wait under the watch, of a kind (Ranks::waits), on ranks a and b (−1: none; both −1: every rank),
// `what` naming it.
struct Waiting {
    explicit Waiting(int kind, int a = -1, int b = -1, const char* what = "a halo exchange") : kind(kind) {
        Watch& w = watch_state();
        w.peer[0] = a, w.peer[1] = b;
        w.what = what;
        w.since = Watch::now();
    }
    ~Waiting() {
        Watch& w = watch_state();
        w.waited[kind] += (Watch::now() - w.since) * 1e-9;
        w.since = 0;
    }
    int kind;
};
enum { halo_wait, reduction_wait, broadcast_wait, gather_wait };

// MPI counts and offsets are int: a message beyond 2^31 − 1 elements is refused, not truncated.
int mpi_count(long n) {
    if (n > std::numeric_limits<int>::max())
        throw std::length_error("a message of " + std::to_string(n) +
                                " elements among the fluid's ranks exceeds MPI's 2^31 - 1: use more ranks");
    return static_cast<int>(n);
}

template <class T> MPI_Datatype type();
template <> MPI_Datatype type<double>() {
    return MPI_DOUBLE;
}
template <> MPI_Datatype type<char>() {
    return MPI_CHAR;
}

} // namespace

Ranks& Ranks::world() {
    static Session session;
    static Ranks r = [] {
        Ranks x;
        if (session.on) {
            MPI_Comm_rank(MPI_COMM_WORLD, &x.rank_);
            MPI_Comm_size(MPI_COMM_WORLD, &x.size_);
        }
        x.first_.assign(x.size_ + 1, 0);
        return x;
    }();
    return r;
}

void Ranks::divide(const std::vector<double>& cost, int min_rows) {
    const int ny = static_cast<int>(cost.size());
    if (ny < size_ * min_rows)
        throw std::invalid_argument(std::to_string(ny) + " rows cannot be divided into " +
                                    std::to_string(size_) + " blocks of at least " +
                                    std::to_string(min_rows) + " rows (the halo): use fewer ranks");
    std::vector<double> prefix(ny + 1, 0.0);
    for (int j = 0; j < ny; ++j)
        prefix[j + 1] = prefix[j] + cost[j];
    first_.assign(size_ + 1, 0);
    first_[size_] = ny;
    // Block r ends at the row where the running cost is nearest r + 1 shares of the total, kept within the
    // rows that leave every block at least min_rows.
    for (int r = 1; r < size_; ++r) {
        const double target = prefix[ny] * r / size_;
        int j = static_cast<int>(std::lower_bound(prefix.begin(), prefix.end(), target) - prefix.begin());
        if (j > 0 && target - prefix[j - 1] < prefix[j] - target) --j;
        j = std::clamp(j, first_[r - 1] + min_rows, ny - (size_ - r) * min_rows);
        first_[r] = j;
    }
}

double Ranks::imbalance(const std::vector<double>& cost) const {
    double total = 0, worst = 0;
    for (int r = 0; r < size_; ++r) {
        double c = 0;
        for (int j = first_[r]; j < first_[r + 1]; ++j)
            c += cost[j];
        total += c, worst = std::max(worst, c);
    }
    return total > 0 ? worst * size_ / total : 1.0;
}

template <class T> void Ranks::exchange_rows(T* rows, long row, int depth) const {
    if (size_ == 1 || depth <= 0) return;
    MPI_Request q[4];
    post_rows(rows, row, depth, q);
    Waiting w(halo_wait, rank_ > 0 ? rank_ - 1 : -1, rank_ + 1 < size_ ? rank_ + 1 : -1);
    MPI_Waitall(4, q, MPI_STATUSES_IGNORE);
}
// The four messages of one exchange (exchange()): the first and last `depth` rows of the block (padded row
// r = j + 1: the block is padded rows [begin + 1, end + 1)) out, the neighbours' into the rows beyond it.
template <class T> void Ranks::post_rows(T* rows, long row, int depth, void* requests) const {
    auto* q = static_cast<MPI_Request*>(requests);
    const long b = begin() + 1, e = end() + 1, n = row * depth;
    const int down = rank_ > 0 ? rank_ - 1 : MPI_PROC_NULL;
    const int up = rank_ + 1 < size_ ? rank_ + 1 : MPI_PROC_NULL;
    const int c = mpi_count(n);
    MPI_Irecv(rows + (b - depth) * row, c, type<T>(), down, 1, MPI_COMM_WORLD, &q[0]);
    MPI_Irecv(rows + e * row, c, type<T>(), up, 2, MPI_COMM_WORLD, &q[1]);
    MPI_Isend(rows + b * row, c, type<T>(), down, 2, MPI_COMM_WORLD, &q[2]);
    MPI_Isend(rows + (e - depth) * row, c, type<T>(), up, 1, MPI_COMM_WORLD, &q[3]);
}
void Ranks::exchange(double* rows, long row, int depth) const {
    exchange_rows(rows, row, depth);
}
struct Ranks::Pending {
    std::vector<MPI_Request> q;
};
void Ranks::exchange(const std::vector<Rows>& x) const {
    post(x);
    complete();
}
void Ranks::post(const std::vector<Rows>& x) const {
    if (size_ == 1) return;
    if (!pending_) pending_ = std::make_shared<Pending>();
    if (!pending_->q.empty()) throw std::logic_error("Ranks::post before the last post() was completed");
    // Messages between two ranks with one tag arrive in the order sent: the list's order matches them.
    pending_->q.resize(4 * x.size());
    for (size_t k = 0; k < x.size(); ++k)
        post_rows(x[k].rows, x[k].row, x[k].depth, &pending_->q[4 * k]);
}
void Ranks::progress() const {
    if (size_ == 1 || !pending_ || pending_->q.empty()) return;
    int done = 0;
    MPI_Testall(static_cast<int>(pending_->q.size()), pending_->q.data(), &done, MPI_STATUSES_IGNORE);
}
void Ranks::complete() const {
    if (size_ == 1 || !pending_ || pending_->q.empty()) return;
    std::vector<MPI_Request>& q = pending_->q;
    Waiting w(halo_wait, rank_ > 0 ? rank_ - 1 : -1, rank_ + 1 < size_ ? rank_ + 1 : -1);
    MPI_Waitall(static_cast<int>(q.size()), q.data(), MPI_STATUSES_IGNORE);
    q.clear();
}
void Ranks::exchange(char* rows, long row, int depth) const {
    exchange_rows(rows, row, depth);
}

template <class T> void Ranks::share_rows(T* rows, long row) const {
    if (size_ == 1) return;
    std::vector<int> count(size_), offset(size_);
    for (int r = 0; r < size_; ++r)
        count[r] = mpi_count((first_[r + 1] - first_[r]) * row),
        offset[r] = mpi_count((first_[r] + 1) * row);
    Waiting w(gather_wait, -1, -1, "a share of the state");
    MPI_Allgatherv(MPI_IN_PLACE, 0, type<T>(), rows, count.data(), offset.data(), type<T>(), MPI_COMM_WORLD);
}
void Ranks::share(double* rows, long row) const {
    share_rows(rows, row);
}
void Ranks::share(char* rows, long row) const {
    share_rows(rows, row);
}

void Ranks::max(std::vector<double>& v) const {
    if (size_ == 1) return;
    Waiting w(reduction_wait, -1, -1, "a reduction");
    MPI_Allreduce(MPI_IN_PLACE, v.data(), mpi_count(static_cast<long>(v.size())), MPI_DOUBLE, MPI_MAX,
                  MPI_COMM_WORLD);
}

long Ranks::sum(long v) const {
    if (size_ == 1) return v;
    long s = 0;
    Waiting w(reduction_wait, -1, -1, "a reduction");
    MPI_Allreduce(&v, &s, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    return s;
}

// A broadcast from the root waits on it; from another rank (the one that failed), on every rank.
std::string Ranks::broadcast(const std::string& text, int from) const {
    if (size_ == 1) return text;
    int n = mpi_count(static_cast<long>(text.size()));
    Waiting w(broadcast_wait, from == 0 && !root() ? 0 : -1, -1, "a broadcast from it");
    MPI_Bcast(&n, 1, MPI_INT, from, MPI_COMM_WORLD);
    std::string out = rank_ == from ? text : std::string(n, '\0');
    MPI_Bcast(out.data(), n, MPI_CHAR, from, MPI_COMM_WORLD);
    return out;
}

std::vector<double> Ranks::broadcast(const std::vector<double>& v, int from) const {
    if (size_ == 1) return v;
    long n = static_cast<long>(v.size());
    Waiting w(broadcast_wait, from == 0 && !root() ? 0 : -1, -1, "a broadcast from it");
    MPI_Bcast(&n, 1, MPI_LONG, from, MPI_COMM_WORLD);
    std::vector<double> out = rank_ == from ? v : std::vector<double>(n);
    MPI_Bcast(out.data(), mpi_count(n), MPI_DOUBLE, from, MPI_COMM_WORLD);
    return out;
}

std::vector<double> Ranks::gather(const std::vector<double>& v) const {
    if (size_ == 1) return v;
    const int n = mpi_count(static_cast<long>(v.size()));
    std::vector<int> count(size_), offset(size_);
    Waiting w(gather_wait, -1, -1, "a gather to rank 0");
    MPI_Gather(&n, 1, MPI_INT, count.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<double> out;
    if (root()) {
        for (int r = 1; r < size_; ++r)
            offset[r] = mpi_count(static_cast<long>(offset[r - 1]) + count[r - 1]);
        out.resize(offset[size_ - 1] + count[size_ - 1]);
    }
    MPI_Gatherv(v.data(), n, MPI_DOUBLE, out.data(), count.data(), offset.data(), MPI_DOUBLE, 0,
                MPI_COMM_WORLD);
    return out;
}

void Ranks::gather_all(const std::vector<double>& mine, const std::vector<int>& count,
                       std::vector<double>& out) const {
    if (size_ == 1) {
        out = mine;
        return;
    }
    std::vector<int> offset(size_, 0);
    for (int r = 1; r < size_; ++r)
        offset[r] = mpi_count(static_cast<long>(offset[r - 1]) + count[r - 1]);
    out.resize(static_cast<size_t>(offset[size_ - 1]) + count[size_ - 1]);
    Waiting w(gather_wait, -1, -1, "a gather");
    MPI_Allgatherv(mine.data(), count[rank_], MPI_DOUBLE, out.data(), count.data(), offset.data(), MPI_DOUBLE,
                   MPI_COMM_WORLD);
}

void Ranks::watch(double seconds, bool (*stopped)()) const {
    Watch& w = watch_state();
    if (size_ == 1 || w.thread.joinable()) return;
    w.limit = seconds > 0 ? seconds : std::numeric_limits<double>::infinity();
    w.stopped = stopped, w.rank = rank_, w.size = size_;
    w.thread = std::thread([&w] { w.run(); });
}

void Ranks::at_step(long step) const {
    watch_state().step = step;
}

std::vector<double> Ranks::waits() const {
    const Watch& w = watch_state();
    return std::vector<double>(w.waited, w.waited + wait_kinds);
}

void Ranks::abort(const std::string& why, int status) const {
    std::cerr << why << std::endl;
    MPI_Abort(MPI_COMM_WORLD, status);
    std::exit(status);
}

} // namespace undex::fluid
