list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/atomic_file.cpp
  ${CMAKE_CURRENT_LIST_DIR}/read_file.cpp
  ${CMAKE_CURRENT_LIST_DIR}/json_nesting.cpp
  ${CMAKE_CURRENT_LIST_DIR}/confined_folder.cpp
  ${CMAKE_CURRENT_LIST_DIR}/temporaries.cpp
  ${CMAKE_CURRENT_LIST_DIR}/read_log.cpp
  ${CMAKE_CURRENT_LIST_DIR}/temporary_files.cpp
  ${CMAKE_CURRENT_LIST_DIR}/exr.cpp
  ${CMAKE_CURRENT_LIST_DIR}/exr_stream.cpp
  ${CMAKE_CURRENT_LIST_DIR}/image_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mip_texture.cpp
  ${CMAKE_CURRENT_LIST_DIR}/png.cpp
  ${CMAKE_CURRENT_LIST_DIR}/image_sink.cpp
  ${CMAKE_CURRENT_LIST_DIR}/write_image.cpp
)
# The output sinks io/sink_list.h names, one file each: a new sink is its file and its line there.
file(STRINGS ${CMAKE_CURRENT_LIST_DIR}/sink_list.h anamorph_sink_lines REGEX "^ANAMORPH_SINK\\(")
foreach(anamorph_sink_line IN LISTS anamorph_sink_lines)
  string(REGEX REPLACE "^ANAMORPH_SINK\\([A-Za-z0-9_]+, *([A-Za-z0-9_.]+)\\).*$" "\\1" anamorph_sink_file
         "${anamorph_sink_line}")
  list(APPEND ANAMORPH_SOURCES ${CMAKE_CURRENT_LIST_DIR}/${anamorph_sink_file})
endforeach()
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/sink_list.h)
