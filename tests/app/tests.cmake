anamorph_add_test(test_cli
  ${CMAKE_CURRENT_LIST_DIR}/cli_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/isa_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_cli_test.cpp
)
add_dependencies(test_cli anamorph)
include(${CMAKE_CURRENT_LIST_DIR}/scenes_tests.cmake)
anamorph_add_test(test_bad_input
  ${CMAKE_CURRENT_LIST_DIR}/bad_input_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/input_kinds_test.cpp
)
add_dependencies(test_bad_input anamorph)
anamorph_add_test(test_layering
  ${CMAKE_CURRENT_LIST_DIR}/layering_test.cpp
)
anamorph_add_test(test_table_camera
  ${CMAKE_CURRENT_LIST_DIR}/table_camera_test.cpp
)
add_dependencies(test_table_camera anamorph)
anamorph_add_test(test_checkpoint
  ${CMAKE_CURRENT_LIST_DIR}/checkpoint_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/checkpoint_damage_test.cpp
)
add_dependencies(test_checkpoint anamorph)
anamorph_add_test(test_memory
  ${CMAKE_CURRENT_LIST_DIR}/memory_test.cpp
)
add_dependencies(test_memory anamorph)
anamorph_add_test(test_tile_stats
  ${CMAKE_CURRENT_LIST_DIR}/tile_stats_test.cpp
)
add_dependencies(test_tile_stats anamorph)
anamorph_add_test(test_mpi
  ${CMAKE_CURRENT_LIST_DIR}/mpi_test.cpp
)
target_link_libraries(test_mpi PRIVATE anamorph_dist)
target_compile_definitions(test_mpi PRIVATE ANAMORPH_HAVE_MPI=$<BOOL:${ANAMORPH_HAVE_MPI}>)
add_dependencies(test_mpi anamorph)
anamorph_add_test(test_outputs
  ${CMAKE_CURRENT_LIST_DIR}/outputs_test.cpp
)
add_dependencies(test_outputs anamorph)
anamorph_add_test(test_signals
  ${CMAKE_CURRENT_LIST_DIR}/signals_test.cpp
)
add_dependencies(test_signals anamorph)
anamorph_add_test(test_honest
  ${CMAKE_CURRENT_LIST_DIR}/honest_test.cpp
)
add_dependencies(test_honest anamorph)
anamorph_add_test(test_stmap_cli
  ${CMAKE_CURRENT_LIST_DIR}/stmap_cli_test.cpp
)
add_dependencies(test_stmap_cli anamorph)
anamorph_add_test(test_calib_cli
  ${CMAKE_CURRENT_LIST_DIR}/calib_cli_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vision_cli_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/solve_cli_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/solve_frames_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/solve_goals_test.cpp
)
add_dependencies(test_calib_cli anamorph)
