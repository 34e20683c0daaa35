// undex-rigid CASE [--set key=value]... --couple ENDPOINT: the rigid-plate structure solver
// (solid/rigid.hpp).
#include "base/solver_main.hpp"
#include "solid/rigid.hpp"

int main(int argc, char** argv) {
    return undex::solver_main(argc, argv, "undex-rigid", undex::solid::run_rigid);
}
