anamorph_add_test(test_render
  ${CMAKE_CURRENT_LIST_DIR}/shapes_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/integrator_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/determinism_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/texture_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/adaptive_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/metrics_test.cpp
)
