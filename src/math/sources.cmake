list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/transform.cpp
  ${CMAKE_CURRENT_LIST_DIR}/rigid_motion.cpp
  ${CMAKE_CURRENT_LIST_DIR}/rbf.cpp
  ${CMAKE_CURRENT_LIST_DIR}/user_text.cpp
  ${CMAKE_CURRENT_LIST_DIR}/simd.cpp
)
