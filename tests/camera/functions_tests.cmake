anamorph_add_test(test_camera_functions
  ${CMAKE_CURRENT_LIST_DIR}/org_function_test.cpp
)
