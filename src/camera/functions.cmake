list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/org_common.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_basic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_quadric.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_revolution.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_superquadric.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bspline.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spline_surface.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_spline.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_expression.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dir_basic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dir_dependent.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dir_expression.cpp
  ${CMAKE_CURRENT_LIST_DIR}/registry.cpp
)
