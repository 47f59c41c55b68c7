list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/virtual_camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_basic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dir_basic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/registry.cpp
  ${CMAKE_CURRENT_LIST_DIR}/presets.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_perspective.cpp
)
