cell-sim_LDLIBS := -linih -lpcap -ljansson
