# Smoke renders of every bundled scene (examples/paper, examples/apps) at a small size.
anamorph_add_test(test_scenes_smoke
  ${CMAKE_CURRENT_LIST_DIR}/scenes_smoke_test.cpp
)
