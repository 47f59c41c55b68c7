# Bounds on what anamorph reads (math/input_limits.h, issue 32 part 2): every recursive reader's
# depth limit, coordinates of any size through the reader, the renderer and the editor, and the
# second probe's crashes from the command line. Links the editor's server for its API.
anamorph_add_test(test_limits
  ${CMAKE_CURRENT_LIST_DIR}/depth_limit_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/coordinate_range_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/crash_regression_test.cpp
)
target_link_libraries(test_limits PRIVATE anamorph_server anamorph_test_http nlohmann_json::nlohmann_json
                      tomlplusplus::tomlplusplus)
add_dependencies(test_limits anamorph)
