list(APPEND ANAMORPH_SOURCES  # anamorph warp's pixels and textures (above camera and io)
  ${CMAKE_CURRENT_LIST_DIR}/warp_texture.cpp
  ${CMAKE_CURRENT_LIST_DIR}/oiio_texture_source.cpp
  ${CMAKE_CURRENT_LIST_DIR}/warp_rows.cpp
)
