// HDF5 output of a fluid run with an XDMF sidecar for ParaView. Layout of <dir>/fluid.h5:
//   datasets    case (text of the case after overrides), status ("running", "complete" or "failed:
//               <message>"): scalar fixed-length strings, null-padded (base/h5.hpp)
//   attributes  dim, nx, ny, degree, variables, basis_functions, x_min, x_max, y_min, y_max
//   /fields/NNNNNN   attributes time, step, last_good (1 for the state written after a failure), mass and
//                    energy (∫ρ and ∫E over the fluid, planar measure);
//                    rho, u, v, p [, void_fraction] [, phi] [, phi_s]: cell averages (phi: level set of two
//                    fluids; phi_s: signed distance to the structure's nearest wet face, < 0 in the fluid,
//                    ±(band + 2 cells) beyond where it is computed; inside the structure the other fields
//                    hold the nearest face's ghost or last state),
//                    shape (ny, nx) in 2D, (nx) in 1D; coefficients: modal DG coefficients, shape (cells,
//                    variables·basis_functions)
//   /frames/NNNNNN   2D, with output.frame_interval: attribute time; p, rho, phi, void_fraction (float32,
//                    shape (ceil(ny / stride), ceil(nx / stride))), block averages of the cell averages
//                    (phi 1 where there is one fluid, void_fraction 0 without cavitation); /frames has the
//                    attributes stride, x_min, x_max, y_min, y_max, nx, ny (of the mesh)
//   /gauges/NAME     t, rho, u, v, p: time series at the gauge point
//   /interface       coupled runs, per step. 1D: t, dt, p_L, u_L, Z_L, p_I, u_I, displacement, dt_f, dt_s;
//                    2D: t, dt, dt_f, dt_s, work (Σ_k p_I u_I A_k Δt of the step), total_work
//   /wet_nodes       2D coupled runs, at every fields output after the first step, per wet node: t, node,
//   face,
//                    x, y (end of the step), p_L, u_L, p_I, u_I, area (of the positions at the start of the
//                    step)
// On many ranks (docs/scale_out.md) each rank writes the fields of its own rows to
// <dir>/fluid.parts/rankNNNN.h5 (OutputPart), and the field datasets of fluid.h5 are HDF5 virtual datasets
// that join the ranks' rows (h5::write_virtual): h5py, ParaView and undex read them as those of one rank.
// The file is flushed after every write, so a run that stops leaves every completed output readable;
// fluid.xmf lists the outputs flushed and is replaced whole (h5::write_file_atomically). A write that fails
// throws h5::Error naming the file, the object and the cause.
#pragma once
#include "base/h5.hpp"
#include "base/run_plan.hpp"
#include "fluid/solver.hpp"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace undex::fluid {

class Output {
  public:
    // Creates <directory>/fluid.h5 (replacing an older one) and fluid.xmf; the rank files of an older run
    // that this one, on `ranks` ranks, does not write again are removed.
    Output(const std::string& directory, const std::string& case_text, const FluidSolver& solver,
           const std::vector<GaugePoint>& gauges, int ranks = 1);
    // Resuming from a checkpoint: the existing <directory>/fluid.h5 with what it held at the checkpoint (the
    // outputs written after it deleted), and the gauges' series so far.
    Output(const std::string& directory, const FluidSolver& solver, const std::vector<GaugePoint>& gauges,
           State& checkpoint);
    Output(const Output&) = delete;
    Output& operator=(const Output&) = delete;

    void write_fields(const FluidSolver& solver, bool last_good = false);
    // Many ranks: the same, joining the rows the ranks wrote (rank r rows [first_row[r], first_row[r + 1]),
    // OutputPart::write_fields of this output done and flushed on every rank); row_totals: every row's
    // (FluidSolver::row_totals, rank after rank).
    void write_fields(const FluidSolver& solver, const std::vector<int>& first_row,
                      const std::vector<double>& row_totals, bool last_good = false);
    // A light frame (/frames/NNNNNN): cell averages of p, rho, phi, void_fraction in single precision,
    // averaged over blocks of stride × stride cells (the last block of a row or column may be smaller).
    void write_frame(const FluidSolver& solver, int stride);
    // The same from the cells' p, rho, phi, void fraction (frame_cells of every row, in order): on many
    // ranks each gives its own rows.
    void write_frame(const std::vector<double>& cells, double time, int stride);

    void record_gauges(const FluidSolver& solver);
    // The same with the gauges' states at time t given (many ranks: evaluated by the rank that holds each).
    void record_gauges(double t, const std::vector<Primitive>& w);
    void write_gauges();
    // Status "complete", the file closed.
    void complete();
    // h5::OutputFile::fail: the last good state (write_state), status "failed: WHY", the file closed.
    void fail(const std::string& why, const std::function<void()>& write_state);
    // A table as one dataset per column in group (created on first use), rows interleaved in data.
    void write_table(const std::string& group, const std::vector<std::string>& columns,
                     const std::vector<double>& data);
    const std::string& path() const { return file_.path(); }
    // What a checkpoint holds of the output: the gauges' series, the outputs written.
    void state(State& s);

  private:
    void describe(const FluidSolver& solver);
    // fields/NNNNNN with its attributes; then the datasets, then finish_fields.
    h5::Object begin_fields(const FluidSolver& solver, const std::vector<double>& totals, bool last_good);
    void finish_fields(h5::Object& group, double time);
    void write_xdmf() const;
    h5::OutputFile file_;
    std::vector<GaugePoint> gauges_;
    std::vector<std::vector<double>> series_; // per gauge: t, rho, u, v, p interleaved
    struct Snapshot {
        std::string group;
        double time;
    };
    std::vector<Snapshot> snapshots_;
    int count_ = 0;  // field outputs tried
    int frames_ = 0; // frames written
    int dim_ = 1, nx_ = 0, ny_ = 1;
    double x_min_ = 0, y_min_ = 0, dx_ = 1, dy_ = 1;
    bool cavitation_ = false, level_set_ = false, structure_ = false;
};

// One rank's part of the field outputs of a run on many ranks: <directory>/fluid.parts/rankNNNN.h5 (an
// h5::OutputFile: case, status) with fields/NNNNNN holding the rank's rows as fluid.h5 would, rows
// [first_row, first_row + rows) (attributes), cell fields of shape (rows, nx) and coefficients of shape
// (rows · nx, variables · basis_functions). Written by every rank for every output, in the same order.
class OutputPart {
  public:
    OutputPart(const std::string& directory, int rank, const std::string& case_text);
    static std::string name(int rank); // fluid.parts/rankNNNN.h5, relative to the output directory
    void write_fields(const FluidSolver& solver, int j0, int j1);
    void complete() { file_.complete(); }
    void fail(const std::string& why) {
        file_.fail(why, [] {});
    }

  private:
    h5::OutputFile file_;
    int count_ = 0;
};

// Reading back (for `undex-fluid --sample`; base/h5.hpp reads the rest).
std::vector<double> read_coefficients(const std::string& h5_path, const std::string& group);
// Level set φ of a two-fluid run (empty for one fluid).
std::vector<double> read_level_set(const std::string& h5_path, const std::string& group);

// p, rho, phi (1 without a level set) and the void fraction of the cells of rows [j0, j1) (for frames).
std::vector<double> frame_cells(const FluidSolver& solver, int j0, int j1);

} // namespace undex::fluid
