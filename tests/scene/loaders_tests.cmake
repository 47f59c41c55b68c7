anamorph_add_test(test_loaders
  ${CMAKE_CURRENT_LIST_DIR}/loader_gltf_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/loader_assimp_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/loader_shared_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_scene_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/isolated_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/fuzz_regression_test.cpp
)
