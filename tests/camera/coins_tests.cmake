anamorph_add_test(test_camera_coins
  ${CMAKE_CURRENT_LIST_DIR}/coin_test.cpp
)
