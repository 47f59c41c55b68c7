// The processes of a render: one, or the ranks of an MPI job (`mpirun -np N anamorph render`).
// Rank 0 is the head: it decides what to render, hands tiles out on demand and writes the files.
// The other ranks are workers: each loads the scene itself and renders the tiles it is given.
#pragma once

#include <string>

namespace anamorph::dist {

// Whether this build has MPI (found at configure time).
bool built_with_mpi();
// The MPI library, as `--version` reports it: "Open MPI v4.1.4", or "none".
std::string mpi_library();

// MPI's lifetime. When the process was started by mpirun or srun and the build has MPI, MPI is
// initialised here and finalised by the destructor; otherwise this is a single process, rank 0
// of 1 (a build without MPI started by mpirun says so and every rank renders alone).
class World {
 public:
  World(int* argc, char*** argv);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  static int rank();
  static int size();
  // The job is ending after an interruption: the other ranks are aborted rather than waited for
  // (one of them may be dead, and that is why).
  static void abort_on_exit(int code);
};

}  // namespace anamorph::dist
