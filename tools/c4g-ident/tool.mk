# c4g-ident (C++17): Ceres Solver and Eigen for the fit, jansson for --json, libpcap through
# c4g-replay's capture reader and analysis (compiled in), gnuplot at run time for --plot.
c4g-ident_EXTRA_CSRCS := tools/c4g-replay/capture.c tools/c4g-replay/analyze.c
c4g-ident_CXXFLAGS := -isystem /usr/include/eigen3 -Itools/c4g-replay
c4g-ident_LDLIBS := -lceres -lglog -lpcap -ljansson -linih -lpthread
