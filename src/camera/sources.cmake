list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/virtual_camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/key_derivative.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ray_kernels.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ray_field.cpp
)
include(${CMAKE_CURRENT_LIST_DIR}/functions.cmake)  # origin and direction functions
include(${CMAKE_CURRENT_LIST_DIR}/presets.cmake)    # presets
include(${CMAKE_CURRENT_LIST_DIR}/coins.cmake)      # centers of interest
list(APPEND ANAMORPH_SOURCES  # source projections and STMaps (anamorph stmap, warp)
  ${CMAKE_CURRENT_LIST_DIR}/source_projections.cpp
  ${CMAKE_CURRENT_LIST_DIR}/source_equirect.cpp
  ${CMAKE_CURRENT_LIST_DIR}/source_cubemap.cpp
  ${CMAKE_CURRENT_LIST_DIR}/source_fisheye.cpp
  ${CMAKE_CURRENT_LIST_DIR}/source_perspective.cpp
  ${CMAKE_CURRENT_LIST_DIR}/stmap.cpp
)
