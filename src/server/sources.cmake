# The editor's server (`anamorph serve`): HTTP on Boost.Beast (header-only, from libboost-dev), the
# editor's state and preview, and the page from web/ built into the binary. Linked into the
# executable only.
find_package(Boost 1.74 REQUIRED)
find_package(Threads REQUIRED)
set(ANAMORPH_WEB_FILES index.html style.css app.js api.js document.js preview.js fields.js
    panels.js scene_panels.js overlay.js surface.js overview.js navigate.js timeline.js drag.js pins.js)
set(web_dir ${PROJECT_SOURCE_DIR}/web)
list(TRANSFORM ANAMORPH_WEB_FILES PREPEND ${web_dir}/ OUTPUT_VARIABLE web_paths)
set(web_cpp ${CMAKE_CURRENT_BINARY_DIR}/web_assets.cpp)
string(REPLACE ";" "," web_names "${ANAMORPH_WEB_FILES}")
add_custom_command(OUTPUT ${web_cpp}
  COMMAND ${CMAKE_COMMAND} -DWEB_DIR=${web_dir} -DNAMES=${web_names} -DOUT=${web_cpp}
          -P ${CMAKE_CURRENT_LIST_DIR}/embed_web.cmake
  DEPENDS ${web_paths} ${CMAKE_CURRENT_LIST_DIR}/embed_web.cmake
  COMMENT "Building the editor's page into the binary" VERBATIM)
add_library(anamorph_server STATIC
  ${CMAKE_CURRENT_LIST_DIR}/http_server.cpp
  ${CMAKE_CURRENT_LIST_DIR}/http_headers.cpp
  ${CMAKE_CURRENT_LIST_DIR}/document.cpp
  ${CMAKE_CURRENT_LIST_DIR}/document_save.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preview.cpp
  ${CMAKE_CURRENT_LIST_DIR}/editor.cpp
  ${CMAKE_CURRENT_LIST_DIR}/editor_views.cpp
  ${CMAKE_CURRENT_LIST_DIR}/editor_solve.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_json.cpp
  ${CMAKE_CURRENT_LIST_DIR}/api_routes.cpp
  ${web_cpp})
# (its headers name toml++ and nlohmann::json types: their users compile them the same way)
# (the pin tool's live solve is src/solve's, the library behind `anamorph solve`)
target_link_libraries(anamorph_server PUBLIC anamorph_core anamorph_solve Boost::headers Threads::Threads
                      nlohmann_json::nlohmann_json tomlplusplus::tomlplusplus
                      PRIVATE anamorph_warnings)
