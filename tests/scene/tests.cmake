include(${CMAKE_CURRENT_LIST_DIR}/loaders_tests.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/parser_tests.cmake)
