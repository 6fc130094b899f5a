cell-sim_LDLIBS := -linih -ljansson
