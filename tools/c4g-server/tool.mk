c4g-server_LDLIBS := -linih -lpthread -lpcap -ljansson
