/* SPDX-License-Identifier: MIT */
/* Runs on a big-endian 32-bit ARM under qemu-armeb (Linux user mode, no C library: the
 * toolchain has no big-endian newlib): the cyclic codec's byte-order path. A little-endian
 * wire packet is decoded and its values checked, encoded back byte for byte, and a NaN and
 * an unknown mode are refused; an initialization packet (one copy of its words into
 * c4g_init_t, reversed word by word here) likewise. Exit status: 0, or the number of the first failed check. */
#include "c4gopen.h"

#include <stddef.h>

/* The library needs these four; a hosted test gets them from the C library. */
void *memcpy(void *dst, const void *src, size_t n);
void *memmove(void *dst, const void *src, size_t n);
void *memset(void *dst, int c, size_t n);
int memcmp(const void *x, const void *y, size_t n);
void _start(void);

void *memcpy(void *dst, const void *src, size_t n)
{
    unsigned char *a = dst;
    const unsigned char *b = src;
    while (n-- > 0U) {
        *a++ = *b++;
    }
    return dst;
}

void *memmove(void *dst, const void *src, size_t n)
{
    unsigned char *a = dst;
    const unsigned char *b = src;
    if (a < b) {
        while (n-- > 0U) {
            *a++ = *b++;
        }
    } else {
        a += n;
        b += n;
        while (n-- > 0U) {
            *--a = *--b;
        }
    }
    return dst;
}

void *memset(void *dst, int c, size_t n)
{
    unsigned char *a = dst;
    while (n-- > 0U) {
        *a++ = (unsigned char)c;
    }
    return dst;
}

int memcmp(const void *x, const void *y, size_t n)
{
    const unsigned char *a = x;
    const unsigned char *b = y;
    for (; n > 0U; n--, a++, b++) {
        if (*a != *b) {
            return *a - *b;
        }
    }
    return 0;
}

/* Linux exit(2) through the EABI system call. */
static void sys_exit(int code)
{
    register int r0 __asm__("r0") = code;
    register int r7 __asm__("r7") = 1;
    __asm__ volatile("svc 0" : : "r"(r0), "r"(r7));
    for (;;) {
    }
}

#define AXES 3U
#define LEN (12U + (36U * AXES))

static uint8_t wire[C4G_MAX_CYCLIC_SIZE];
static uint8_t out[C4G_MAX_CYCLIC_SIZE];
static c4g_ctrl_packet_t pkt;

/* A little-endian word, written byte by byte whatever the host. */
static void put_le(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static uint32_t bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static uint8_t init_wire[C4G_INIT_SIZE];
static uint8_t init_out[C4G_INIT_SIZE];
static c4g_init_t init;

/* An initialization packet of two open axes on arm 0: decoded values, diagnostics, the
 * encoder's bytes. */
static int run_init(void)
{
    c4g_diag_t d;
    size_t n = 0U;
    uint32_t k;
    put_le(init_wire, 10U);
    put_le(&init_wire[4], 3U);
    put_le(&init_wire[8], 9U);
    put_le(&init_wire[12], 2U);
    put_le(&init_wire[C4G_INIT_OFF_PERIOD], 2U);
    for (k = 0U; k < 40U; k++) {
        put_le(&init_wire[C4G_INIT_OFF_OPENAX + (4U * k)], (k < 2U) ? k : 0xFFU);
        put_le(&init_wire[C4G_INIT_OFF_AZLIM + (4U * k)], (k < 2U) ? 0x41200000U : 0U); /* 10 A */
    }
    put_le(&init_wire[C4G_INIT_OFF_CALDATA + 4U], 0x3FC00000U); /* 1.5 */
    put_le(&init_wire[C4G_INIT_OFF_VERSION + 8U], 115U);
    if ((c4g_init_decode(init_wire, sizeof init_wire, &init, &d) != C4G_OK) || (init.n_ax_open != 2) ||
        (init.open_ax[0][1] != 1) || (init.open_ax[0][2] != 0xFF) || (init.period_ms != 2) ||
        (bits(init.cal_data[0][1]) != 0x3FC00000U) || (bits(init.az_lim[0][1]) != 0x41200000U) ||
        (init.version_build != 115)) {
        return 10;
    }
    if ((c4g_init_encode(&init, init_out, sizeof init_out, &n) != C4G_OK) || (n != C4G_INIT_SIZE) ||
        (memcmp(init_out, init_wire, C4G_INIT_SIZE) != 0)) {
        return 11;
    }
    put_le(&init_wire[C4G_INIT_OFF_AZLIM + 4U], 0x7FC00000U); /* NaN: arm 0, axis 1 */
    if ((c4g_init_decode(init_wire, sizeof init_wire, &init, &d) != C4G_ERR_NONFINITE) ||
        (d.field != C4G_FIELD_AZLIM) || (d.axis != 1) || (d.offset != C4G_INIT_OFF_AZLIM + 4U)) {
        return 12;
    }
    put_le(&init_wire[C4G_INIT_OFF_AZLIM + 4U], 0U); /* an open axis without current */
    if ((c4g_init_decode(init_wire, sizeof init_wire, &init, &d) != C4G_ERR_RANGE) || (d.axis != 1)) {
        return 13;
    }
    return 0;
}

static int run(void)
{
    c4g_diag_t d;
    size_t n = 0U;
    uint32_t i;
    uint32_t k;
    put_le(wire, 1234U);
    put_le(&wire[4], 0x0505U);
    put_le(&wire[8], 7U);
    for (i = 0U; i < AXES; i++) {
        put_le(&wire[12U + (36U * i)], 4U);
        for (k = 1U; k < 9U; k++) { /* 1.0f plus a few ulps: every field distinct */
            put_le(&wire[12U + (36U * i) + (4U * k)], 0x3F800000U + (16U * i) + k);
        }
    }
    if (c4g_ctrl_decode(wire, LEN, 0U, &pkt, NULL) != C4G_OK) {
        return 1;
    }
    if ((pkt.num != 1234) || (pkt.infpar != 0x0505U) || (pkt.cmd != 7U) || (pkt.n_axes != AXES) ||
        (pkt.ax[2].mode != C4G_MODE_4)) {
        return 2;
    }
    if ((bits(pkt.ax[1].target_vel) != 0x3F800000U + 16U + 2U) ||
        (bits(pkt.ax[2].ext[2]) != 0x3F800000U + 32U + 8U)) {
        return 3;
    }
    if ((c4g_ctrl_encode(&pkt, out, sizeof out, &n) != C4G_OK) || (n != LEN) ||
        (memcmp(out, wire, LEN) != 0)) {
        return 4;
    }
    put_le(&wire[12U + 36U + 12U], 0x7FC00000U); /* NaN: axis 1, D3 */
    if ((c4g_ctrl_decode(wire, LEN, 0U, &pkt, &d) != C4G_ERR_NONFINITE) || (d.axis != 1) ||
        (d.field != C4G_FIELD_D3)) {
        return 5;
    }
    put_le(&wire[12U + 36U + 12U], 0x3F800000U);
    put_le(&wire[12U + 72U], 99U); /* unknown mode: axis 2 */
    if (c4g_ctrl_decode(wire, LEN, 0U, &pkt, NULL) != C4G_ERR_MODE) {
        return 6;
    }
    put_le(&wire[12U + 72U], 4U);
    if (c4g_ctrl_decode(wire, LEN, 0U, &pkt, NULL) != C4G_OK) {
        return 7;
    }
    memcpy(&pkt.ax[0].actual_vel, &(uint32_t){0x7F800000U}, 4U); /* +inf */
    if (c4g_ctrl_encode(&pkt, out, sizeof out, &n) != C4G_ERR_NONFINITE) {
        return 8;
    }
    memcpy(&pkt.ax[0].actual_vel, &(uint32_t){0x3F800000U}, 4U);
    /* NaN words just past the axes (the caller's, unchecked) do not refuse the packet */
    memcpy(&pkt.ax[AXES].mode, &(uint32_t){0x7FC00000U}, 4U);
    memcpy(&pkt.ax[AXES].target_pos, &(uint32_t){0xFF800000U}, 4U);
    if ((c4g_ctrl_encode(&pkt, out, sizeof out, &n) != C4G_OK) || (n != LEN)) {
        return 9;
    }
    return 0;
}

void _start(void)
{
    int r = run();
    sys_exit((r != 0) ? r : run_init());
}
