include(${CMAKE_CURRENT_LIST_DIR}/loaders_tests.cmake)
