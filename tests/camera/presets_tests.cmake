anamorph_add_test(test_camera_presets
  ${CMAKE_CURRENT_LIST_DIR}/perspective_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_common_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_fisheye_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_opencv_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_map_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_ods_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_light_field_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_cubemap_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_multiperspective_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/preset_docs_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dof_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/batch_test.cpp
)

# Makes the pictures and parameter tables of docs/cameras.md (not a test; run by hand):
#   build/tests/camera_preset_gallery images docs/images/cameras
#   build/tests/camera_preset_gallery tables docs/cameras.md
add_executable(camera_preset_gallery ${CMAKE_CURRENT_LIST_DIR}/preset_gallery.cpp)
target_link_libraries(camera_preset_gallery PRIVATE anamorph_core anamorph_warnings)
