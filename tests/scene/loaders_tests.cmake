# anamorph_add_test(test_loaders ...)
