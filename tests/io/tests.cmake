anamorph_add_test(test_io
  ${CMAKE_CURRENT_LIST_DIR}/atomic_write_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/exr_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/image_sink_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mip_texture_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/nul_path_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/png_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/read_image_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/read_file_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/srgb_test.cpp
)
# exr_test inspects the written header with tinyexr directly.
target_link_libraries(test_io PRIVATE tinyexr::tinyexr)
