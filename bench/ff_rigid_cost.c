/* SPDX-License-Identifier: MIT */
/* Cost of mode 9's rigid-body model per tick (c4gh_ffr_current: the controller's motor
 * targets to the link side, the clamp, c4g_dyn_model_rnea with the rotors, Kr^-T, the currents
 * and friction of every motor) on the arm plant's exact file
 * (fixtures/server/ff_rigid_example.ini, 6 axes), over 1000 precomputed states of a
 * six-axis move. bench/tick_cost.sh runs it under callgrind with N and 2N ticks and prints
 * (Ir(2N) - Ir(N)) / N beside the mode-4 full tick; alone it prints ns per tick.
 * Usage: ff_rigid_cost [TICKS] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "c4gh_ffmodel.h"
#include "c4gsim_fixtures.h"

#define STATES 1000
#define AX 6

static double qm[STATES][AX], vm[STATES][AX], am[STATES][AX];

int main(int argc, char **argv)
{
    static c4gh_ffm_file_t m;
    c4gh_ffr_t r;
    c4gh_ffr_out_t o;
    c4g_init_t init;
    c4g_kin_t kin;
    char err[512];
    const long n = (argc > 1) ? atol(argv[1]) : 200000L;
    double sum = 0.0;
    struct timespec t0, t1;
    long k;
    int s, j;
    if (c4gh_ffm_load("fixtures/server/ff_rigid_example.ini", &m, err, sizeof err) != 0) {
        fprintf(stderr, "ff_rigid_cost: %s\n", err);
        return 1;
    }
    (void)c4gsim_fig10_1(&init);
    if (c4g_kin_from_init(&init, 0U, &kin) != C4G_OK || c4gh_ffr_setup(&r, &m, &kin) != 0) {
        fprintf(stderr, "ff_rigid_cost: the transmission\n");
        return 1;
    }
    for (s = 0; s < STATES; s++) { /* a smooth move of every axis, inside the range */
        for (j = 0; j < AX; j++) {
            const double w = 6.283185307179586 * (0.5 + 0.1 * j), t = s * 0.002;
            qm[s][j] = kin.cal[j] + 5.0 * sin(w * t);
            vm[s][j] = 5.0 * w * cos(w * t);
            am[s][j] = -5.0 * w * w * sin(w * t);
        }
    }
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (k = 0; k < n; k++) {
        const int i = (int)(k % STATES);
        if (c4gh_ffr_current(&r, qm[i], vm[i], am[i], &o) != 0) {
            fprintf(stderr, "ff_rigid_cost: not evaluable at state %d\n", i);
            return 1;
        }
        sum += o.cur[k % AX];
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("ticks %ld ns/tick %.1f (checksum %.6g)\n", n,
           ((double)(t1.tv_sec - t0.tv_sec) * 1e9 + (double)(t1.tv_nsec - t0.tv_nsec)) / (double)n, sum);
    return 0;
}
