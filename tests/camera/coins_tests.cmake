anamorph_add_test(test_camera_coins
  ${CMAKE_CURRENT_LIST_DIR}/coin_test.cpp
)

# Makes the plots and pictures of docs/coins.md (not a test; run by hand):
#   build/tests/camera_coin_gallery docs/images/coins
add_executable(camera_coin_gallery ${CMAKE_CURRENT_LIST_DIR}/coin_gallery.cpp)
target_link_libraries(camera_coin_gallery PRIVATE anamorph_core anamorph_warnings)
