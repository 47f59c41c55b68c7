list(APPEND ANAMORPH_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/param_toml.cpp
  ${CMAKE_CURRENT_LIST_DIR}/toml_parse.cpp
  ${CMAKE_CURRENT_LIST_DIR}/param_docs.cpp
  ${CMAKE_CURRENT_LIST_DIR}/read_params.cpp
  ${CMAKE_CURRENT_LIST_DIR}/param_schema.cpp
)
