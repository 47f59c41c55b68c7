list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/loaders.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_loader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/assimp_loader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/assimp_child.cpp
  ${CMAKE_CURRENT_LIST_DIR}/isolated.cpp
  ${CMAKE_CURRENT_LIST_DIR}/load_validate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/load_common.cpp
  ${CMAKE_CURRENT_LIST_DIR}/load_gltf_accessor.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_rig_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_animation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_lights.cpp
  ${CMAKE_CURRENT_LIST_DIR}/skinning.cpp
  ${CMAKE_CURRENT_LIST_DIR}/load_mesh_repair.cpp
)
