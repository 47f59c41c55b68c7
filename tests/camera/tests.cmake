include(${CMAKE_CURRENT_LIST_DIR}/functions_tests.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/presets_tests.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/coins_tests.cmake)
