// SPDX-License-Identifier: MIT
// Times c4g-ident's per-axis fit (ident::fit: linear start, robust Ceres passes, covariance)
// on the samples `c4g-ident fit --samples DIR` wrote, best of N runs, for the comparison with
// scipy.optimize.least_squares on the same data (bench/ident_scipy.py).
//   ident_fit [--runs N] FILE.csv...   prints: file samples variant seconds Ja Fv Fc off Fs vs ga gb
#include "ident.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

using namespace ident;

static bool load(const char *path, Samples *s, Variant *v, double *eps)
{
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line)) return false;
    const std::size_t vp = line.find(" variant "), ep = line.find(" eps ");
    if (vp == std::string::npos || ep == std::string::npos) return false;
    const std::string vn = line.substr(vp + 9, line.find(' ', vp + 9) - (vp + 9));
    *eps = std::atof(line.c_str() + ep + 5);
    bool found = false;
    for (int k = 0; k < NVARIANT; k++) {
        if (vn == variant_name[k]) {
            *v = static_cast<Variant>(k);
            found = true;
        }
    }
    if (!found || !std::getline(in, line)) return false;
    while (std::getline(in, line)) {
        double x[5];
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &x[0], &x[1], &x[2], &x[3], &x[4]) != 5) return false;
        s->v.push_back(x[0]);
        s->a.push_back(x[1]);
        s->i.push_back(x[2]);
        s->cq.push_back(x[3]);
        s->sq.push_back(x[4]);
    }
    return s->n() > 0;
}

int main(int argc, char **argv)
{
    int runs = 3, first = 1;
    if (argc > 2 && std::strcmp(argv[1], "--runs") == 0) {
        runs = std::max(1, std::atoi(argv[2]));
        first = 3;
    }
    if (first >= argc) {
        std::fprintf(stderr, "usage: ident_fit [--runs N] FILE.csv...\n");
        return 2;
    }
    for (int f = first; f < argc; f++) {
        Samples s;
        Variant v = COULOMB;
        double eps = 0.0;
        if (!load(argv[f], &s, &v, &eps)) {
            std::fprintf(stderr, "ident_fit: %s: not a c4g-ident samples file\n", argv[f]);
            return 1;
        }
        Options o;
        o.threads = 1;
        double best = 1e300;
        Fit F;
        for (int r = 0; r < runs; r++) {
            const auto t0 = std::chrono::steady_clock::now();
            F = fit(s, v, eps, o);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        std::printf("%s %zu %s %.6f", argv[f], s.n(), variant_name[v], best);
        for (int k = 0; k < NPARAM; k++) std::printf(" %.9g", F.p[static_cast<std::size_t>(k)]);
        std::printf("\n");
    }
    return 0;
}
