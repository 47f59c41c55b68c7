list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/scene.cpp
  ${CMAKE_CURRENT_LIST_DIR}/shape.cpp
  ${CMAKE_CURRENT_LIST_DIR}/world_extent.cpp
)
include(${CMAKE_CURRENT_LIST_DIR}/loaders.cmake)  # glTF and assimp loaders
list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/toml_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/toml_edit.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene_schema.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene_docs.cpp
  ${CMAKE_CURRENT_LIST_DIR}/declarations.cpp
  ${CMAKE_CURRENT_LIST_DIR}/animation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/camera_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/camera_goals.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene_pose.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_scene.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene_loader.cpp
)
