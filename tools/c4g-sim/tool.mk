# c4g-sim links inih (INI configuration) and libpcap (--pcap).
c4g-sim_LDLIBS := -linih -lpcap
