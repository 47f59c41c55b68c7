#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <cstdlib>

#include "dist/world.h"

namespace anamorph::dist {

namespace {

int g_rank = 0, g_size = 1;
bool g_initialised = false;
int g_abort_code = -1;

// mpirun (Open MPI, MPICH) and srun (PMI/PMIx) mark the processes they start.
bool started_by_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}

}  // namespace

bool built_with_mpi() { return true; }

std::string mpi_library() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);  // (callable before MPI_Init)
  std::string v(text, size_t(std::max(length, 0)));
  v = v.substr(0, v.find_first_of(",\n"));  // "Open MPI v4.1.4, package: ..." -> the name
  return v.empty() ? "MPI" : v;
}

World::World(int* argc, char*** argv) {
  if (!started_by_launcher()) return;
  int provided = 0;
  // Only the thread that called main talks to MPI; render threads never do.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_initialised = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
}

World::~World() {
  if (!g_initialised) return;
  if (g_abort_code >= 0) MPI_Abort(MPI_COMM_WORLD, g_abort_code);
  MPI_Finalize();
}

int World::rank() { return g_rank; }
int World::size() { return g_size; }
void World::abort_on_exit(int code) { g_abort_code = code; }

}  // namespace anamorph::dist
