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
  ${CMAKE_CURRENT_LIST_DIR}/png.cpp
)
