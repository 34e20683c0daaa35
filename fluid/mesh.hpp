// Uniform Cartesian mesh, 1D or 2D, with one layer of ghost cells on every side.
#pragma once

namespace undex::fluid {

struct Mesh {
    int dim = 1;
    int nx = 0, ny = 1; // interior cells (ny = 1 in 1D)
    double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
    double dx = 1, dy = 1;
    int alpha = 0; // geometric factor of physics.md §1

    int padded_nx() const { return nx + 2; }
    int padded_ny() const { return dim == 2 ? ny + 2 : 1; }
    int padded_cells() const { return padded_nx() * padded_ny(); }
    // Cell (i, j) with i ∈ [−1, nx], j ∈ [−1, ny] (j = 0 in 1D); −1 and nx, ny are ghosts.
    int index(int i, int j) const { return dim == 2 ? (j + 1) * (nx + 2) + (i + 1) : i + 1; }
    // Cell centres measured from the domain's centre, so that mirror-image cells of a domain symmetric
    // about 0 (or about x = y) get centres that are exact mirror images.
    double xc(int i) const { return 0.5 * (x_min + x_max) + (i - 0.5 * (nx - 1)) * dx; }
    double yc(int j) const { return dim == 2 ? 0.5 * (y_min + y_max) + (j - 0.5 * (ny - 1)) * dy : 0.0; }
};

} // namespace undex::fluid
