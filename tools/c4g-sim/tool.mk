# c4g-sim links inih (INI configuration), libpcap (--pcap) and jansson (--json).
c4g-sim_LDLIBS := -linih -lpcap -ljansson
