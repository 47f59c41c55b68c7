list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/adaptive.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bsdf.cpp
  ${CMAKE_CURRENT_LIST_DIR}/checkpoint.cpp
  ${CMAKE_CURRENT_LIST_DIR}/coin_layer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/film.cpp
  ${CMAKE_CURRENT_LIST_DIR}/form_factors.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_output.cpp
  ${CMAKE_CURRENT_LIST_DIR}/surface_sampler.cpp
  ${CMAKE_CURRENT_LIST_DIR}/image_metrics.cpp
  ${CMAKE_CURRENT_LIST_DIR}/integrators.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lights.cpp
  ${CMAKE_CURRENT_LIST_DIR}/render_job.cpp
  ${CMAKE_CURRENT_LIST_DIR}/renderer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/shading.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tile_buffer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tile_sampler.cpp
)
