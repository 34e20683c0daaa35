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
    double xc(int i) const { return x_min + (i + 0.5) * dx; }
    double yc(int j) const { return dim == 2 ? y_min + (j + 0.5) * dy : 0.0; }
};

} // namespace undex::fluid
