# Tiles and frames across MPI ranks. Its own library, linked into the executable only (not the
# Python module). Without MPI the build still works: every process renders alone.
option(ANAMORPH_MPI "Render across MPI ranks when MPI is found (mpirun -np N anamorph render)" ON)
if(ANAMORPH_MPI)
  find_package(MPI COMPONENTS CXX QUIET)
endif()
if(ANAMORPH_MPI AND MPI_CXX_FOUND)
  add_library(anamorph_dist STATIC ${CMAKE_CURRENT_LIST_DIR}/head.cpp
              ${CMAKE_CURRENT_LIST_DIR}/worker.cpp ${CMAKE_CURRENT_LIST_DIR}/wire.cpp
              ${CMAKE_CURRENT_LIST_DIR}/world_mpi.cpp)
  target_link_libraries(anamorph_dist PUBLIC MPI::MPI_CXX)
  set(ANAMORPH_HAVE_MPI ON CACHE INTERNAL "")
else()
  add_library(anamorph_dist STATIC ${CMAKE_CURRENT_LIST_DIR}/no_mpi.cpp
              ${CMAKE_CURRENT_LIST_DIR}/wire.cpp)
  set(ANAMORPH_HAVE_MPI OFF CACHE INTERNAL "")
endif()
target_link_libraries(anamorph_dist PUBLIC anamorph_core PRIVATE anamorph_warnings)
message(STATUS "anamorph: rendering across MPI ranks: ${ANAMORPH_HAVE_MPI}")
