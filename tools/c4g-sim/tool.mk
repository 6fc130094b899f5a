# c4g-sim links inih (INI configuration), libpcap (--pcap), jansson (--json) and MuJoCo (the
# arm plant, --plant).
c4g-sim_LDLIBS := -linih -lpcap -ljansson -lmujoco
