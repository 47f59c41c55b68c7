list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/presets.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_util.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_perspective.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_orthographic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_fisheye.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_opencv.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_cylindrical.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_stereographic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_panini.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_cubemap.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_ods.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_light_field.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_multiperspective.cpp
)
