anamorph_add_test(test_camera
  ${CMAKE_CURRENT_LIST_DIR}/perspective_test.cpp
)
