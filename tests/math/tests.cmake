anamorph_add_test(test_math
  ${CMAKE_CURRENT_LIST_DIR}/fast_trig_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/qmc_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/transform_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/user_text_test.cpp
)
