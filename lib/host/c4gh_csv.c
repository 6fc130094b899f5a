/* SPDX-License-Identifier: MIT */
/* CSV text of monitoring records and the float format the tools share. A tool helper, not
 * part of the real-time library: no stdio, so the same bytes come out on every target. */
#include "c4gh_csv.h"

#include <string.h>

#define N_VALUES 5U
#define FIXED_LIMIT 1.0e9
#define SCALE 1000000.0
#define SCALE_U 1000000U

static uint32_t f32_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static int type_ok(uint32_t type)
{
    return (type >= C4G_MONI_FIRST) && (type <= C4G_MONI_LAST);
}


typedef struct out_buf {
    char *p;
    size_t cap;
    size_t len;
    int overflow;
} out_buf_t;

static void put_char(out_buf_t *o, char c)
{
    /* one byte is always kept for the terminating NUL */
    if ((o->len + 1U) < o->cap) {
        o->p[o->len] = c;
        o->len++;
    } else {
        o->overflow = 1;
    }
}

static void put_str(out_buf_t *o, const char *s)
{
    size_t i = 0U;
    while (s[i] != '\0') {
        put_char(o, s[i]);
        i++;
    }
}

/* Decimal digits of @p v, at least @p min_digits (zero padded). */
static void put_u64(out_buf_t *o, uint64_t v, uint32_t min_digits)
{
    static const char digits[] = "0123456789";
    char d[24];
    uint32_t n = 0U;
    uint64_t x = v;
    do {
        d[n] = digits[x % 10U];
        x /= 10U;
        n++;
    } while ((x != 0U) && (n < 20U));
    while (n < min_digits) {
        d[n] = '0';
        n++;
    }
    while (n > 0U) {
        n--;
        put_char(o, d[n]);
    }
}

static void put_i64(out_buf_t *o, int64_t v)
{
    if (v < 0) {
        put_char(o, '-');
        put_u64(o, (uint64_t)(-(v + 1)) + 1U, 1U);
    } else {
        put_u64(o, (uint64_t)v, 1U);
    }
}

/* |d| < 1e9: fixed point, C4GH_MONI_DECIMALS decimals, round half away from zero. */
static void put_fixed(out_buf_t *o, double d, int neg)
{
    const double r = (d * SCALE) + 0.5;
    const uint64_t u = (uint64_t)r;
    if ((neg != 0) && (u != 0U)) {
        put_char(o, '-');
    }
    put_u64(o, u / SCALE_U, 1U);
    put_char(o, '.');
    put_u64(o, u % SCALE_U, C4GH_MONI_DECIMALS);
}

/* |d| >= 1e9 (float: below 3.5e38): d.dddddde+XX. */
static void put_sci(out_buf_t *o, double d, int neg)
{
    double m = d;
    double r;
    uint32_t e = 0U;
    uint32_t k;
    uint64_t u;
    for (k = 0U; k < 40U; k++) { /* float: at most 10^38 */
        if (m >= 10.0) {
            m /= 10.0;
            e++;
        }
    }
    /* No carry into a new digit is possible: adjacent floats differ by at least 2^-24
     * relative, more than the 5e-8 rounding window just below a power of ten. */
    r = (m * SCALE) + 0.5;
    u = (uint64_t)r;
    if (neg != 0) {
        put_char(o, '-');
    }
    put_u64(o, u / SCALE_U, 1U);
    put_char(o, '.');
    put_u64(o, u % SCALE_U, C4GH_MONI_DECIMALS);
    put_str(o, "e+");
    put_u64(o, e, 2U);
}

static void put_float(out_buf_t *o, float v)
{
    const uint32_t bits = f32_bits(v);
    int neg = 0;
    if ((bits & 0x80000000U) != 0U) {
        neg = 1;
    }
    if ((bits & 0x7F800000U) == 0x7F800000U) {
        if ((bits & 0x007FFFFFU) != 0U) {
            put_str(o, "nan");
        } else {
            put_str(o, (neg != 0) ? "-inf" : "inf");
        }
    } else {
        const double d = (neg != 0) ? -(double)v : (double)v;
        if (d < FIXED_LIMIT) {
            put_fixed(o, d, neg);
        } else {
            put_sci(o, d, neg);
        }
    }
}

static c4g_status_t finish_out(out_buf_t *o, size_t *len)
{
    c4g_status_t st = C4G_ERR_CAPACITY;
    if ((o->overflow == 0) && (o->cap > 0U)) {
        o->p[o->len] = '\0';
        *len = o->len;
        st = C4G_OK;
    } else {
        if (o->cap > 0U) {
            o->p[0] = '\0';
        }
        *len = 0U;
    }
    return st;
}

c4g_status_t c4gh_fmt_float(float v, char *buf, size_t cap, size_t *len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((buf != NULL) && (len != NULL)) {
        out_buf_t o = {NULL, 0U, 0U, 0};
        o.p = buf;
        o.cap = cap;
        put_float(&o, v);
        st = finish_out(&o, len);
    }
    return st;
}

c4g_status_t c4gh_moni_csv_header(uint32_t type, char *buf, size_t cap, size_t *len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((buf != NULL) && (len != NULL)) {
        st = C4G_ERR_ARG;
        *len = 0U;
        if (type_ok(type)) {
            out_buf_t o = {NULL, 0U, 0U, 0};
            uint32_t k;
            o.p = buf;
            o.cap = cap;
            put_str(&o, "type,num,axis,mode");
            for (k = 0U; k < N_VALUES; k++) {
                put_char(&o, ',');
                put_str(&o, c4g_moni_value_name(type, k));
            }
            put_char(&o, '\n');
            st = finish_out(&o, len);
        }
    }
    return st;
}

c4g_status_t c4gh_moni_csv_row(const c4g_moni_rec_t *rec, char *buf, size_t cap, size_t *len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((rec != NULL) && (buf != NULL) && (len != NULL)) {
        st = C4G_ERR_ARG;
        *len = 0U;
        if (type_ok(rec->type)) {
            out_buf_t o = {NULL, 0U, 0U, 0};
            uint32_t k;
            o.p = buf;
            o.cap = cap;
            put_u64(&o, rec->type, 1U);
            put_char(&o, ',');
            put_i64(&o, rec->num);
            put_char(&o, ',');
            put_u64(&o, rec->axis, 1U);
            put_char(&o, ',');
            put_i64(&o, rec->mode);
            for (k = 0U; k < N_VALUES; k++) {
                put_char(&o, ',');
                put_float(&o, rec->v[k]);
            }
            put_char(&o, '\n');
            st = finish_out(&o, len);
        }
    }
    return st;
}


void c4gh_tick_csv_row(FILE *f, double t_s, int32_t num, uint32_t axis, uint32_t arm,
                      uint32_t logical, const c4g_ctrl_axis_t *rx, uint32_t tx_infpar,
                      const c4g_pc_axis_t *tx)
{
    fprintf(f, "%.6f,%d,%u,%u,%u,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%u,%d,%.9g,%.9g,%.9g,"
            "%.9g,%.9g", t_s, (int)num, (unsigned)axis, (unsigned)arm, (unsigned)logical,
            (int)rx->mode, (double)rx->target_pos, (double)rx->target_vel, (double)rx->actual_pos,
            (double)rx->actual_vel, (double)rx->current_ref, (double)rx->ext[0],
            (double)rx->ext[1], (double)rx->ext[2], (unsigned)tx_infpar, (int)tx->mode,
            (double)tx->target_pos, (double)tx->target_vel, (double)tx->measure,
            (double)tx->vel_add, (double)tx->current_add);
}
