/* SPDX-License-Identifier: MIT */
/* c4g-sim's controller and plant in process, no sockets: N ticks of sim_tick at 1 ms (two DSA
 * steps each) while arm 1 moves back and forth in mode 0, with the decoupled plant or the arm
 * plant (--plant FILE). Prints the CPU ns per tick (CLOCK_PROCESS_CPUTIME_ID over the ticks
 * alone). bench/sim_plant_cost.sh runs it, and under callgrind.
 * Usage: sim_plant [--plant FILE] TICKS */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "scenario.h"
#include "sim.h"

static sim_t g_sim;
static scn_t g_scn;

int main(int argc, char **argv)
{
    static char text[16384];
    sim_config_t cfg;
    c4g_ctrl_packet_t out;
    struct timespec t0, t1;
    char err[256];
    unsigned long n;
    unsigned long t;
    size_t len = 0;
    int i;
    sim_config_default(&cfg);
    cfg.period_ms = 1;
    if (argc == 4 && strcmp(argv[1], "--plant") == 0) {
        snprintf(cfg.plant.path, sizeof cfg.plant.path, "%s", argv[2]);
        argv += 2;
        argc -= 2;
    }
    if (argc != 2 || (n = strtoul(argv[1], NULL, 10)) == 0UL) {
        fprintf(stderr, "usage: sim_plant [--plant FILE] TICKS\n");
        return 2;
    }
    len += (size_t)snprintf(text + len, sizeof text - len, "DRIVE ON 1\n");
    for (i = 0; i < 200; i++) {
        len += (size_t)snprintf(text + len, sizeof text - len,
                                "MOVE 1 2 -1.5 1 0.5 -0.5 0.25\nMOVE 1 0 0 0 0 0 0\n");
    }
    if (scn_parse("bench.scn", text, len, &g_scn, err, sizeof err) != 0 ||
        sim_init(&g_sim, &cfg, &g_scn, NULL) != 0) {
        fprintf(stderr, "sim_plant: %s %s\n", err, g_sim.init_err);
        return 1;
    }
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    for (t = 0; t < n; t++) {
        sim_tick(&g_sim, NULL, &out);
    }
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    printf("%.0f\n", ((double)(t1.tv_sec - t0.tv_sec) * 1e9 + (double)(t1.tv_nsec - t0.tv_nsec)) / (double)n);
    if (g_sim.n_err != 0) {
        fprintf(stderr, "sim_plant: %s\n", g_sim.err[0].text);
        return 1;
    }
    sim_free(&g_sim);
    return 0;
}
