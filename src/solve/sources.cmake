# The camera solver (`anamorph solve`, docs/solve.md, and Python's Camera.solve): its own library,
# the only one linking Ceres Solver (libceres-dev), so that the core and the tests do not pay for
# it.
find_package(Ceres REQUIRED)
add_library(anamorph_solve STATIC
  ${CMAKE_CURRENT_LIST_DIR}/free_params.cpp
  ${CMAKE_CURRENT_LIST_DIR}/goals.cpp
  ${CMAKE_CURRENT_LIST_DIR}/goals_jacobian.cpp
  ${CMAKE_CURRENT_LIST_DIR}/camera_solve.cpp)
target_link_libraries(anamorph_solve PUBLIC anamorph_core
                      PRIVATE anamorph_warnings Ceres::ceres tomlplusplus::tomlplusplus)
# Position-independent: the Python module (a shared object) links it too.
set_target_properties(anamorph_solve PROPERTIES POSITION_INDEPENDENT_CODE ON)
