# c4g-ident (C++17): Ceres Solver and Eigen for the fit, jansson for --json, libpcap through
# the host archive's capture reader and analysis, gnuplot at run time for --plot.
c4g-ident_CXXFLAGS := -isystem /usr/include/eigen3
c4g-ident_LDLIBS := -lceres -lglog -lpcap -ljansson -linih -lpthread
