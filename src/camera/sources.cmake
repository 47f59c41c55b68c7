list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/virtual_camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ray_kernels.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ray_field.cpp
)
include(${CMAKE_CURRENT_LIST_DIR}/functions.cmake)  # origin and direction functions
include(${CMAKE_CURRENT_LIST_DIR}/presets.cmake)    # presets
include(${CMAKE_CURRENT_LIST_DIR}/coins.cmake)      # centers of interest
