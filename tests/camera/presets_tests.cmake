anamorph_add_test(test_camera_presets
  ${CMAKE_CURRENT_LIST_DIR}/perspective_test.cpp
)
