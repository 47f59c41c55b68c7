set(ANAMORPH_APP_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/main.cpp
  ${CMAKE_CURRENT_LIST_DIR}/common.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cmd_render.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cmd_info.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cmd_camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cmd_bench.cpp
)
