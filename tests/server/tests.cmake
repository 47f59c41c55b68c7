# The tests' HTTP client (Boost.Beast), compiled once for every test binary that talks to a server.
find_package(Boost 1.74 REQUIRED)
add_library(anamorph_test_http STATIC ${CMAKE_CURRENT_LIST_DIR}/http_client.cpp)
target_include_directories(anamorph_test_http PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(anamorph_test_http PRIVATE Boost::headers anamorph_warnings anamorph_sanitize)

# The editor's server (src/server) in the test's own process, over loopback HTTP.
anamorph_add_test(test_server
  ${CMAKE_CURRENT_LIST_DIR}/api_security_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_edit_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_files_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_confinement_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_preview_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_camera_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_solve_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/solve_jacobian_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_declarations_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_fuzz_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/document_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/document_save_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/examples_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/render_cancel_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/http_server_test.cpp
)
# (the server is a library of its own; its headers name toml++ and nlohmann::json types)
target_link_libraries(test_server PRIVATE anamorph_server anamorph_test_http nlohmann_json::nlohmann_json
                      tomlplusplus::tomlplusplus)
