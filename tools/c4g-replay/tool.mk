c4g-replay_LDLIBS := -lpcap -ljansson -linih -lpthread
