# anamorph_add_test(test_camera_functions ...)
