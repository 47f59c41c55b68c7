anamorph_add_test(test_camera_functions
  ${CMAKE_CURRENT_LIST_DIR}/org_function_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spline_function_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/shape_function_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dir_function_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_function_test.cpp
)
