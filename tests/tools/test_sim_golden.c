/* SPDX-License-Identifier: MIT */
/* c4g-sim's controller, run in-process over every mode scenario with a deterministic PC, is
 * bit-identical to a recorded run: the hashes below were taken from the simulator before its
 * model (lib/sim) was restructured, so any change of the model's arithmetic shows here. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "scenario.h"
#include "sim.h"

#define GOLDEN_TICKS 3000

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++) {
        h = (h ^ b[i]) * 0x100000001B3ULL;
    }
    return h;
}

static uint64_t hash_packet(uint64_t h, const c4g_ctrl_packet_t *o)
{
    uint32_t i;
    h = fnv(h, &o->infpar, sizeof o->infpar);
    h = fnv(h, &o->cmd, sizeof o->cmd);
    for (i = 0; i < o->n_axes; i++) {
        h = fnv(h, &o->ax[i], sizeof o->ax[i]);
    }
    return h;
}

/* A PC that echoes each axis's mode and target, with small additions of every kind. */
static void pc_reply(const c4g_ctrl_packet_t *o, unsigned long tick, c4g_pc_packet_t *r)
{
    uint32_t i;
    memset(r, 0, sizeof *r);
    r->n_axes = o->n_axes;
    for (i = 0; i < o->n_axes; i++) {
        r->ax[i].mode = o->ax[i].mode;
        r->ax[i].target_pos = o->ax[i].target_pos + (float)((tick % 7U) * 1e-4);
        r->ax[i].target_vel = o->ax[i].target_vel;
        r->ax[i].vel_add = (float)((tick % 5U) * 2e-5);
        r->ax[i].current_add = (float)((tick % 3U) * 0.05);
    }
}

static uint64_t run_scenario_file(const char *name)
{
    static scn_t scn;
    static sim_t s;
    sim_config_t cfg;
    c4g_ctrl_packet_t out;
    c4g_pc_packet_t reply;
    char path[512];
    char err[256];
    static char text[65536];
    size_t len;
    unsigned long t;
    uint64_t h = 0xCBF29CE484222325ULL;
    FILE *f;
    (void)snprintf(path, sizeof path, "%s/scenarios/%s.scn", FIXTURES_DIR, name);
    f = fopen(path, "rb");
    assert_non_null(f);
    len = fread(text, 1, sizeof text, f);
    (void)fclose(f);
    assert_int_equal(scn_parse(path, text, len, &scn, err, sizeof err), 0);
    sim_config_default(&cfg);
    cfg.seed = 7;
    cfg.ax[0][0].vs = 0.05;        /* Stribeck on axis 1 */
    cfg.ax[0][0].fs = 0.25;
    cfg.ax[0][1].torque_noise = 0.01;
    cfg.ax[0][2].cur_noise = 0.02;
    cfg.ax[0][3].load = 0.1;
    assert_int_equal(sim_init(&s, &cfg, &scn, NULL), 0);
    sim_fill(&s, &out);
    for (t = 0; t < GOLDEN_TICKS; t++) {
        pc_reply(&out, t, &reply);
        sim_tick(&s, (t % 11U == 5U) ? NULL : &reply, &out);
        h = hash_packet(h, &out);
    }
    return h;
}

static void test_golden(void **state)
{
    static const struct { const char *name; uint64_t hash; } runs[] = {
        {"mode0", 0x771A9E8B3298B7ACULL},
        {"mode1", 0x11764F79DC80F6A2ULL},
        {"mode2", 0x9DB6B1C82E1035F3ULL},
        {"mode4", 0x177DFD0F104F6C61ULL},
        {"mode5", 0xBE294F7531A8F902ULL},
        {"mode7", 0x86E40BDE020CD48CULL},
        {"mode8", 0x01B6490AD5398EB2ULL},
        {"mode9", 0x1C79BAE94874CCF8ULL},
        {"mode10", 0xEBB0C5AED4128D57ULL},
        {"freeze", 0xCF8803647277AEB9ULL},
    };
    size_t i;
    int bad = 0;
    (void)state;
    for (i = 0; i < sizeof runs / sizeof runs[0]; i++) {
        const uint64_t h = run_scenario_file(runs[i].name);
        if (h != runs[i].hash) {
            printf("%s: hash 0x%016llX, recorded 0x%016llX\n", runs[i].name, (unsigned long long)h,
                   (unsigned long long)runs[i].hash);
        }
        bad += (h != runs[i].hash);
    }
    assert_int_equal(bad, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
