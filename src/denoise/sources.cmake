list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/least_squares.cpp
  ${CMAKE_CURRENT_LIST_DIR}/nl_means.cpp
  ${CMAKE_CURRENT_LIST_DIR}/regression.cpp
  ${CMAKE_CURRENT_LIST_DIR}/variance.cpp
)
