include(${CMAKE_CURRENT_LIST_DIR}/functions_tests.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/presets_tests.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/coins_tests.cmake)
anamorph_add_test(test_camera_stmap
  ${CMAKE_CURRENT_LIST_DIR}/stmap_test.cpp
)
