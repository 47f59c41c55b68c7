anamorph_add_test(test_camera_presets
  ${CMAKE_CURRENT_LIST_DIR}/perspective_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_common_test.cpp
)
