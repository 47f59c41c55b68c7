list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/org_common.cpp
  ${CMAKE_CURRENT_LIST_DIR}/org_basic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dir_basic.cpp
  ${CMAKE_CURRENT_LIST_DIR}/registry.cpp
)
