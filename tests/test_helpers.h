/* SPDX-License-Identifier: MIT */
/* Shared test helpers: fixture loading, deterministic PRNG, packet builders. */
#ifndef TEST_HELPERS_H
#define TEST_HELPERS_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "c4gh_csv.h"

static inline size_t th_read_file(const char *path, uint8_t *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    size_t n;
    if (f == NULL) {
        fail_msg("cannot open %s", path);
        return 0;
    }
    n = fread(buf, 1, cap, f);
    fclose(f);
    return n;
}

#ifdef TH_FIG10_1
/* The manual's figure 10.1 initialization packet, byte for byte, loaded by the group setup
 * th_load_fig (tests that want it define TH_FIG10_1 before including this header). */
static uint8_t th_fig[C4G_INIT_SIZE];
static int th_load_fig(void **state)
{
    (void)state;
    assert_int_equal(th_read_file(FIXTURES_DIR "/vectors/init-fig10-1.bin", th_fig, sizeof th_fig),
                     C4G_INIT_SIZE);
    return 0;
}
#endif

/* xorshift32: deterministic, seed printed by the tests that use it */
static inline uint32_t th_rand(uint32_t *s)
{
    uint32_t x = *s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *s = x;
    return x;
}

static inline float th_randf(uint32_t *s)
{
    return ((float)(th_rand(s) % 2000001U) - 1000000.0f) / 1000.0f;
}

static inline void th_put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static inline uint32_t th_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static inline void th_put_f32(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    th_put_u32(p, u);
}

/* A controller packet for n axes, mode m on every axis, recognisable data. */
static inline void th_ctrl_packet(c4g_ctrl_packet_t *p, int32_t num, uint32_t n, int32_t mode)
{
    uint32_t i;
    memset(p, 0, sizeof *p);
    p->num = num;
    p->n_axes = n;
    for (i = 0; i < n; i++) {
        p->ax[i].mode = mode;
        p->ax[i].target_pos = 1.0f + (float)i;
        p->ax[i].target_vel = 0.5f * (float)i;
        p->ax[i].actual_pos = 1.25f + (float)i;
        p->ax[i].actual_vel = -0.25f * (float)i;
        p->ax[i].current_ref = 0.1f * (float)i;
        p->ax[i].ext[0] = 7.0f;
        p->ax[i].ext[1] = 8.0f;
        p->ax[i].ext[2] = 9.0f;
    }
}

static inline size_t th_ctrl_bytes(uint8_t *buf, size_t cap, int32_t num, uint32_t n, int32_t mode)
{
    c4g_ctrl_packet_t p;
    size_t len = 0;
    th_ctrl_packet(&p, num, n, mode);
    assert_int_equal(c4g_ctrl_encode(&p, buf, cap, &len), C4G_OK);
    return len;
}

/* A controller packet and a reply with distinct values on axis 2 (moni records, their CSV). */
static inline void moni_packets(c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx)
{
    memset(rx, 0, sizeof *rx);
    memset(tx, 0, sizeof *tx);
    rx->num = 321;
    rx->n_axes = tx->n_axes = 2;
    rx->ax[1].mode = 9;
    rx->ax[1].target_pos = 1.0f;
    rx->ax[1].target_vel = 2.0f;
    rx->ax[1].actual_pos = 3.0f;
    rx->ax[1].actual_vel = 4.0f;
    rx->ax[1].current_ref = 5.0f;
    rx->ax[1].ext[0] = 6.0f;
    rx->ax[1].ext[1] = 7.0f;
    tx->ax[1].mode = 9;
    tx->ax[1].target_pos = 11.0f;
    tx->ax[1].target_vel = 12.0f;
    tx->ax[1].measure = 13.0f;
    tx->ax[1].vel_add = 14.0f;
    tx->ax[1].current_add = 15.0f;
}

#endif
