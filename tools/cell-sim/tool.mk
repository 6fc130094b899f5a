cell-sim_LDLIBS := -linih
