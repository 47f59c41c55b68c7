list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/denoise.cpp
  ${CMAKE_CURRENT_LIST_DIR}/feature_prefilter.cpp
  ${CMAKE_CURRENT_LIST_DIR}/input_checks.cpp
  ${CMAKE_CURRENT_LIST_DIR}/least_squares.cpp
  ${CMAKE_CURRENT_LIST_DIR}/nl_means.cpp
  ${CMAKE_CURRENT_LIST_DIR}/regression.cpp
  ${CMAKE_CURRENT_LIST_DIR}/selection.cpp
  ${CMAKE_CURRENT_LIST_DIR}/variance.cpp
)
# Sanitizer builds compile at -O0 (quick to build), where the denoiser's kernels run about 100×
# slower than at -O2 and its tests would take minutes: its sources keep -O2 there (still fully
# instrumented).
if(ANAMORPH_SANITIZE)
  set_source_files_properties(
    ${CMAKE_CURRENT_LIST_DIR}/denoise.cpp ${CMAKE_CURRENT_LIST_DIR}/feature_prefilter.cpp
    ${CMAKE_CURRENT_LIST_DIR}/nl_means.cpp ${CMAKE_CURRENT_LIST_DIR}/regression.cpp
    ${CMAKE_CURRENT_LIST_DIR}/selection.cpp ${CMAKE_CURRENT_LIST_DIR}/variance.cpp
    ${CMAKE_CURRENT_LIST_DIR}/least_squares.cpp
    PROPERTIES COMPILE_OPTIONS -O2)
endif()
