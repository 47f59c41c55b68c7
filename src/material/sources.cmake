list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/texture.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bsdf.cpp
  ${CMAKE_CURRENT_LIST_DIR}/layers.cpp
  ${CMAKE_CURRENT_LIST_DIR}/material.cpp
  ${CMAKE_CURRENT_LIST_DIR}/material_kinds.cpp
  ${CMAKE_CURRENT_LIST_DIR}/whitted.cpp
  ${CMAKE_CURRENT_LIST_DIR}/metallic_roughness.cpp
  ${CMAKE_CURRENT_LIST_DIR}/unlit.cpp
)
