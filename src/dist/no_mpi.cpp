// A build without MPI (none found at configure time): every process renders alone. Started by
// mpirun anyway, each rank would render the whole job by itself; it says so instead.
#include <fmt/format.h>

#include <cstdlib>
#include <stdexcept>

#include "dist/head.h"
#include "dist/worker.h"
#include "dist/world.h"

namespace anamorph::dist {

bool built_with_mpi() { return false; }
std::string mpi_library() { return "none"; }

World::World(int*, char***) {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!size) size = std::getenv("PMI_SIZE");
  if (size && std::atoi(size) > 1) {
    fmt::print(stderr,
               "error: started by mpirun, but this anamorph was built without MPI (install "
               "libopenmpi-dev and build again, or run it without mpirun)\n");
    std::exit(2);
  }
}
World::~World() = default;
int World::rank() { return 0; }
int World::size() { return 1; }
void World::abort_on_exit(int) {}

struct HeadFarm::Send {};

// Unreachable: size() is 1, so there is neither a head with workers nor a worker.
HeadFarm::HeadFarm(std::vector<Aov>, const std::atomic<bool>*) {
  throw std::logic_error("built without MPI");
}
HeadFarm::~HeadFarm() = default;
void HeadFarm::begin_frame(double) {}
void HeadFarm::run(const std::function<std::optional<FarmTile>()>&,
                   const std::function<void(FarmResult&)>&) {}
int serve_tiles(int, const std::vector<Aov>&, const std::function<WorkerFrame(double)>&) {
  throw std::logic_error("built without MPI");
}

}  // namespace anamorph::dist
