anamorph_add_test(test_denoise
  ${CMAKE_CURRENT_LIST_DIR}/denoise_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/nfor_test.cpp
)
