anamorph_add_test(test_scene_parser
  ${CMAKE_CURRENT_LIST_DIR}/scene_parser_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/animation_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/shutter_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/schema_test.cpp
)
add_dependencies(test_scene_parser anamorph)
