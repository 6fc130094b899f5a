/* SPDX-License-Identifier: MIT */
/* c4g-replay export: one row per cyclic tick (the controller's packet and the reply it got),
 * every field of every axis both ways, as CSV, JSON lines, or the manual's monitoring rows.
 * The fields are read straight from the datagrams, so a NaN the decoder refuses is still
 * exported ("nan" in CSV, null in JSON). */
#include "replay.h"

#include "c4gh_csv.h"
#include "c4gh_fmt.h"
#include "c4gh_textfile.h"

#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ex_ctx {
    rp_common_t c;
    unsigned moni;            /* 19..24, 0 = all fields */
    int json_lines;
    int ticks;                /* the per-tick CSV (docs/csv.md) */
    uint32_t axes;            /* OPEN indexes (bit 0 = 1), 0 = all */
    double from_s, to_s;      /* window since the session's first packet; to < 0: open */
    unsigned session;         /* 0 = all */
    unsigned last_header_axes;/* axis count of the last CSV header written */
    unsigned header_done;
    uint64_t rows;
    FILE *out;
    char *csv;                /* the CSV text not written yet (csv_flush) */
    size_t csv_n, csv_cap;
    int write_failed;
} ex_ctx_t;

static unsigned axes_in(size_t len)
{
    if (len < C4G_CYCLIC_SIZE(1U) || len > C4G_MAX_CYCLIC_SIZE || (len - C4G_HEADER_SIZE) % C4G_AXIS_SIZE != 0U) {
        return 0U;
    }
    return (unsigned)((len - C4G_HEADER_SIZE) / C4G_AXIS_SIZE);
}

static int axis_on(const ex_ctx_t *e, unsigned i) { return e->axes == 0U || (e->axes & (1U << i)) != 0U; }

static const char *const fnames[8] = {"d1", "d2", "d3", "d4", "d5", "ext1", "ext2", "ext3"};

/* The longest header: the 12 fixed columns, then ",c16_mode" and 8 of ",c16_ext1" a side. */
#define HEADER_CAP (128U + 2U * C4G_MAX_AXES * 9U * 9U)

static size_t csv_header(const ex_ctx_t *e, unsigned n, char *out)
{
    static const char fixed[] = "session,tick,time,ctrl_frame,pc_frame,ctrl_num,pc_num,latency_us,"
                                "ctrl_infpar,ctrl_cmd,pc_infpar,pc_cmd";
    size_t len = sizeof fixed - 1U;
    unsigned i, k;
    char side;
    memcpy(out, fixed, len);
    for (side = 'c'; side != 0; side = (side == 'c') ? 'p' : 0) {
        for (i = 0U; i < n; i++) {
            if (!axis_on(e, i)) {
                continue;
            }
            len += (size_t)snprintf(out + len, HEADER_CAP - len, ",%c%u_mode", side, i + 1U);
            for (k = 0U; k < 8U; k++) {
                len += (size_t)snprintf(out + len, HEADER_CAP - len, ",%c%u_%s", side, i + 1U, fnames[k]);
            }
        }
    }
    out[len++] = '\n';
    return len;
}

/* The CSV rows are built in memory and written with one fwrite a megabyte, stdout
 * unbuffered (no copy into stdio's buffer): the fields are short and many (108 floats a
 * row at 6 axes), so stdio's per-call work and printf's format parsing would cost more
 * than the digits. Floats are their shortest text (c4gh_fmt.h). Every
 * writer takes and returns a local cursor: a store through a char pointer may alias a
 * count kept in memory, which would then be reloaded and stored at every character. */
#define ROW_CAP (200U + 2U * C4G_MAX_AXES * (12U + 8U * C4GH_F32_TEXT_MAX))

static const char two_digits[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* The digits of v, the last at end[-1], two at a time. */
static void digits_back(uint64_t v, char *end)
{
    while (v >= 100U) {
        const unsigned d2 = (unsigned)(v % 100U);
        v /= 100U;
        end -= 2;
        memcpy(end, two_digits + 2U * d2, 2U);
    }
    if (v >= 10U) {
        memcpy(end - 2, two_digits + 2U * v, 2U);
    } else {
        end[-1] = (char)('0' + v);
    }
}

static char *put_u64(char *p, uint64_t v)
{
    uint64_t x = v;
    size_t n = 1U;
    if (v < 10U) { /* modes, session numbers */
        *p = (char)('0' + v);
        return p + 1;
    }
    while (x >= 10U) {
        x /= 10U;
        n++;
    }
    digits_back(v, p + n);
    return p + n;
}

static char *put_i64(char *p, int64_t v)
{
    if (v < 0) {
        *p = '-';
        return put_u64(p + 1, (uint64_t)(-(v + 1)) + 1U);
    }
    return put_u64(p, (uint64_t)v);
}

/* Two hex digits a byte from a table. */
static char *put_hex32(char *p, uint32_t v)
{
    static const char hex[] = "0123456789abcdef";
    unsigned k;
    p[0] = '0';
    p[1] = 'x';
    for (k = 0U; k < 4U; k++) {
        const unsigned byte = (v >> (24U - 8U * k)) & 0xFFU;
        p[2U + 2U * k] = hex[byte >> 4];
        p[3U + 2U * k] = hex[byte & 0xFU];
    }
    return p + 10;
}

/* v / 10^decimals with exactly @p decimals digits after the point, v an exact integer
 * (ns or us): what %.9f / %.3f print for v * 1e-9 / v * 1e-3 while the double's error stays
 * far below half a last digit (|v| < 10^15 here; beyond, printf itself). */
static char *put_fixed(char *p, int64_t v, unsigned decimals, double as_double)
{
    static const uint64_t p10[] = {1U, 10U, 100U, 1000U, 10000U, 100000U, 1000000U, 10000000U,
                                   100000000U, 1000000000U};
    uint64_t m, frac;
    unsigned k;
    if (v <= -INT64_C(1000000000000000) || v >= INT64_C(1000000000000000)) {
        return p + snprintf(p, 40U, "%.*f", (int)decimals, as_double);
    }
    if (v < 0) {
        *p++ = '-';
        m = (uint64_t)(-v);
    } else {
        m = (uint64_t)v;
    }
    p = put_u64(p, m / p10[decimals]);
    *p++ = '.';
    frac = m % p10[decimals];
    /* the leading zeros first, then the digits of frac up to the last place */
    for (k = 0U; k < decimals; k++) {
        p[k] = '0';
    }
    if (frac != 0U) {
        digits_back(frac, p + decimals);
    }
    return p + decimals;
}

/* c4g_le_u32, inlined: a call per field is a tenth of the row's cost. */
static uint32_t le_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static char *csv_side(const ex_ctx_t *e, char *p, const uint8_t *d, size_t len, unsigned n)
{
    const unsigned have = (d != NULL) ? axes_in(len) : 0U;
    unsigned i, k;
    for (i = 0U; i < n; i++) {
        const uint8_t *a;
        uint32_t mode;
        if (!axis_on(e, i)) {
            continue;
        }
        if (i >= have) {
            memcpy(p, ",,,,,,,,,", 9U);
            p += 9;
            continue;
        }
        a = d + C4G_HEADER_SIZE + i * C4G_AXIS_SIZE;
        mode = le_u32(a);
        *p++ = ',';
        if (mode < 10U) { /* the modes there are: one digit, no call */
            *p++ = (char)('0' + mode);
        } else {
            p = put_i64(p, c4g_le_i32(a));
        }
        for (k = 0U; k < 8U; k++) {
            /* +0 is "0" (c4gh_fmt.h) without the call: the fields a mode leaves unused
             * are zeros, half of a row or more */
            const uint32_t bits = le_u32(a + 4U + 4U * k);
            *p++ = ',';
            if (bits == 0U) {
                *p++ = '0';
            } else {
                float f;
                memcpy(&f, &bits, sizeof f);
                p += c4gh_fmt_f32(f, p);
            }
        }
    }
    return p;
}

static void csv_flush(ex_ctx_t *e)
{
    if (e->csv_n != 0U && fwrite(e->csv, 1U, e->csv_n, e->out) != e->csv_n) {
        e->write_failed = 1;
    }
    e->csv_n = 0U;
}

static void csv_row(ex_ctx_t *e, const c4gh_an_exchange_t *x, double t)
{
    const unsigned n = axes_in(x->ctrl_len);
    char *p;
    if (e->csv_n > e->csv_cap - (HEADER_CAP + ROW_CAP)) {
        csv_flush(e);
    }
    p = e->csv + e->csv_n;
    if (!e->header_done || n != e->last_header_axes) {
        p += csv_header(e, n, p);
        e->header_done = 1U;
        e->last_header_axes = n;
    }
    p = put_u64(p, x->s->id);
    *p++ = ',';
    p = put_u64(p, x->tick);
    *p++ = ',';
    p = put_fixed(p, x->ctrl_ns - x->s->first_ns, 9U, t);
    *p++ = ',';
    p = put_u64(p, x->ctrl_frame);
    *p++ = ',';
    if (x->reply != NULL) {
        p = put_u64(p, x->reply_frame);
    }
    *p++ = ',';
    p = put_i64(p, c4g_le_i32(x->ctrl));
    *p++ = ',';
    if (x->reply != NULL && x->reply_len >= 4U) {
        p = put_i64(p, c4g_le_i32(x->reply));
        *p++ = ',';
        p = put_fixed(p, x->reply_ns - x->ctrl_ns, 3U, (double)(x->reply_ns - x->ctrl_ns) * 1e-3);
    } else {
        *p++ = ',';
    }
    *p++ = ',';
    p = put_hex32(p, le_u32(x->ctrl + 4));
    *p++ = ',';
    p = put_hex32(p, le_u32(x->ctrl + 8));
    *p++ = ',';
    if (x->reply != NULL && x->reply_len >= C4G_HEADER_SIZE) {
        p = put_hex32(p, le_u32(x->reply + 4));
        *p++ = ',';
        p = put_hex32(p, le_u32(x->reply + 8));
    } else {
        *p++ = ',';
    }
    p = csv_side(e, p, x->ctrl, x->ctrl_len, n);
    p = csv_side(e, p, x->reply, x->reply_len, n);
    *p++ = '\n';
    e->csv_n = (size_t)(p - e->csv);
}

/* A float field: null when it is not finite (JSON has no NaN); as its 9-digit decimal,
 * which gives the float32 back exactly and prints as written (0.1, not 0.100000001490). */
static json_t *json_float(float v)
{
    char text[32];
    if (!isfinite(v)) {
        return json_null();
    }
    (void)snprintf(text, sizeof text, "%.9g", (double)v);
    return json_real(strtod(text, NULL));
}

static json_t *json_side(const ex_ctx_t *e, const uint8_t *d, size_t len)
{
    const unsigned n = axes_in(len);
    unsigned i, k;
    json_t *o, *axes;
    if (d == NULL || n == 0U) {
        return json_null();
    }
    o = json_object();
    axes = json_array();
    json_object_set_new(o, "num", json_integer(c4g_le_i32(d)));
    json_object_set_new(o, "infpar", json_integer(c4g_le_u32(d + 4)));
    json_object_set_new(o, "cmd", json_integer(c4g_le_u32(d + 8)));
    for (i = 0U; i < n; i++) {
        const uint8_t *a = d + C4G_HEADER_SIZE + i * C4G_AXIS_SIZE;
        json_t *ax;
        if (!axis_on(e, i)) {
            continue;
        }
        ax = json_object();
        json_object_set_new(ax, "axis", json_integer(i + 1U));
        json_object_set_new(ax, "mode", json_integer(c4g_le_i32(a)));
        for (k = 0U; k < 8U; k++) {
            json_object_set_new(ax, fnames[k], json_float(c4g_le_f32(a + 4U + 4U * k)));
        }
        json_array_append_new(axes, ax);
    }
    json_object_set_new(o, "axes", axes);
    return o;
}

/* One tick as one JSON object on one line (jansson; 12 significant digits: the floats' 9-digit
 * decimals as they are, the time to the nanosecond below 1000 s). */
static void json_row(ex_ctx_t *e, const c4gh_an_exchange_t *x, double t)
{
    json_t *o = json_object();
    json_object_set_new(o, "session", json_integer(x->s->id));
    json_object_set_new(o, "tick", json_integer((json_int_t)x->tick));
    json_object_set_new(o, "time", json_real(t));
    json_object_set_new(o, "ctrl_frame", json_integer((json_int_t)x->ctrl_frame));
    if (x->reply != NULL) {
        json_object_set_new(o, "pc_frame", json_integer((json_int_t)x->reply_frame));
        json_object_set_new(o, "latency_us", json_real((double)(x->reply_ns - x->ctrl_ns) * 1e-3));
    } else {
        json_object_set_new(o, "pc_frame", json_null());
        json_object_set_new(o, "latency_us", json_null());
    }
    json_object_set_new(o, "verdict", json_string(x->verdict == C4G_CTRL_J_OK ? (x->late ? "late" : "ok")
                                                  : (x->verdict == C4G_CTRL_J_MISSING ? "missing"
                                                                                : "unjudged")));
    json_object_set_new(o, "ctrl", json_side(e, x->ctrl, x->ctrl_len));
    json_object_set_new(o, "pc", json_side(e, x->reply, x->reply_len));
    json_dumpf(o, e->out, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(12));
    fputc('\n', e->out);
    json_decref(o);
}

static void moni_rows(ex_ctx_t *e, const c4gh_an_exchange_t *x)
{
    char buf[C4GH_MONI_ROW_MAX + 8U];
    size_t len = 0U;
    uint32_t i;
    if (x->rx == NULL || x->tx == NULL) {
        return; /* moni records need both packets decoded */
    }
    if (!e->header_done) {
        if (c4gh_moni_csv_header(e->moni, buf, sizeof buf, &len) == C4G_OK) {
            fputs(buf, e->out);
        }
        e->header_done = 1U;
    }
    for (i = 0U; i < x->rx->n_axes; i++) {
        c4g_moni_rec_t rec;
        if (!axis_on(e, i) || c4g_moni_record(e->moni, x->rx, x->tx, i, &rec) != C4G_OK) {
            continue;
        }
        if (c4gh_moni_csv_row(&rec, buf, sizeof buf, &len) == C4G_OK) {
            fputs(buf, e->out);
        }
    }
}

/* The per-tick CSV every tool shares (docs/csv.md): one row per axis, the columns of
 * c4g-server --moni, for ticks whose packet and reply both decoded. */
static void tick_rows(ex_ctx_t *e, const c4gh_an_exchange_t *x, double t)
{
    const c4g_axis_map_t *m = &x->s->map;
    uint32_t i;
    if (x->rx == NULL || x->tx == NULL) {
        return;
    }
    if (!e->header_done) {
        fputs(C4GH_TICK_CSV_COLUMNS "\n", e->out);
        e->header_done = 1U;
    }
    for (i = 0U; i < x->rx->n_axes && i < C4G_MAX_AXES; i++) {
        if (!axis_on(e, i)) {
            continue;
        }
        c4gh_tick_csv_row(e->out, t, x->rx->num, i + 1U, (uint32_t)m->arm_of[i] + 1U,
                         (uint32_t)m->logical_of[i] + 1U, &x->rx->ax[i], x->tx->infpar,
                         &x->tx->ax[i]);
        fputc('\n', e->out);
    }
}

static void on_exchange(void *ctx, const c4gh_an_exchange_t *x)
{
    ex_ctx_t *e = ctx;
    const double t = (double)(x->ctrl_ns - x->s->first_ns) * 1e-9;
    if (x->kind != C4G_PKT_CYCLIC || axes_in(x->ctrl_len) == 0U) {
        return;
    }
    if ((e->session != 0U && x->s->id != e->session) || t < e->from_s || (e->to_s >= 0.0 && t > e->to_s)) {
        return;
    }
    e->rows++;
    if (e->moni != 0U) {
        moni_rows(e, x);
    } else if (e->ticks) {
        tick_rows(e, x, t);
    } else if (e->json_lines) {
        json_row(e, x, t);
    } else {
        csv_row(e, x, t);
    }
}

/* --axes 1,3-5: OPEN indexes 1..20 */
static int opt_axes(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    ex_ctx_t *e = ctx;
    (void)row;
    if (c4gh_cli_parse_axis_list(v, 20U, &e->axes) != 0) {
        (void)snprintf(why, whylen, "want axes 1..20 like 1,3-5");
        return -1;
    }
    return 0;
}

static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_port(&((ex_ctx_t *)ctx)->c, row, v, why, whylen);
}

static const char *const examples[] = {
    RP_TOOL " export fixtures/replay/mode4.pcap > ticks.csv",
    RP_TOOL " export --axes 1-3 --from 0.5 --to 1.5 field.pcap",
    RP_TOOL " export --moni 20 field.pcap > moni20.csv",
    RP_TOOL " export --ticks field.pcap > ticks.csv       # as c4g-server --moni writes",
    RP_TOOL " export --json-lines field.pcap | jq -c 'select(.verdict != \"ok\")'",
    NULL};

static const char epilogue[] =
    "CSV columns: session,tick,time,ctrl_frame,pc_frame,ctrl_num,pc_num,latency_us,ctrl_infpar,\n"
    "ctrl_cmd,pc_infpar,pc_cmd, then per OPEN axis i: ci_mode,ci_d1..ci_d5,ci_ext1..ci_ext3 (the\n"
    "controller's packet) and pi_mode..pi_ext3 (the PC's valid reply, the one to 504 included;\n"
    "empty when none came in time).\n"
    "tick is the cyclic packet's number in its session (1 = the first), time seconds since\n"
    "the session's first packet; each float is its shortest text that reads back to the\n"
    "same float32 (strtof), nan for a NaN, inf / -inf.\n";

int rp_cmd_export(int argc, char **argv)
{
    ex_ctx_t e;
    c4gh_cli_spec_t spec;
    c4gh_an_t a;
    rp_file_t file;
    int first = 0, rc;
    c4gh_cli_result_t r;
    const c4gh_cli_opt_t rows[] = {
        {"moni", 'm', C4GH_CLI_UINT, "TYPE", "the manual's monitoring rows of type 19..24 instead", &e.moni, 0, 19,
         24, NULL, 0},
        {"axes", 0, C4GH_CLI_CALL, "LIST", "OPEN axes to export, e.g. 1,3-5 (default all)", NULL, 0, 0, 0,
         opt_axes, 0},
        {"from", 0, C4GH_CLI_DOUBLE, "S", "first tick at or after S seconds into the session", &e.from_s, 0, 0,
         1e9, NULL, 0},
        {"to", 0, C4GH_CLI_DOUBLE, "S", "last tick at or before S seconds", &e.to_s, 0, 0, 1e9, NULL, 0},
        {"session", 's', C4GH_CLI_UINT, "N", "only session N (summary numbers them)", &e.session, 0, 1, 1e6,
         NULL, 0},
        {"json-lines", 0, C4GH_CLI_FLAG, NULL, "one JSON object per tick instead of CSV", &e.json_lines, 0, 0, 0,
         NULL, 0},
        {"ticks", 0, C4GH_CLI_FLAG, NULL, "the per-tick CSV of c4g-server --moni and c4g-sim --csv instead",
         &e.ticks, 0, 0, 0, NULL, 0},
        {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows (default 1000,1001)", NULL, 0, 0, 0,
         opt_port, 0},
        {"no-progress", 0, C4GH_CLI_FLAG, NULL, "no progress bar on a terminal", &e.c.no_progress, 0, 0, 0, NULL, 0},
    };
    memset(&e, 0, sizeof e);
    rp_common_default(&e.c);
    e.to_s = -1.0;
    e.out = stdout;
    memset(&spec, 0, sizeof spec);
    spec.tool = RP_TOOL;
    spec.command = "export";
    spec.usage = "Usage: " RP_TOOL " export [OPTIONS] FILE\n"
                 "One row per cyclic tick of every session: the controller's packet, the reply,\n"
                 "the reply latency and the NUMs, every field of every axis both ways.\n";
    spec.opts = rows;
    spec.n_opts = sizeof rows / sizeof rows[0];
    spec.examples = examples;
    spec.epilogue = epilogue;
    spec.operands_min = 1;
    spec.operands_max = 1;
    spec.permute = 1;
    r = c4gh_cli_parse(&spec, &e, argc, argv, &first);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    if (e.to_s >= 0.0 && e.to_s < e.from_s) {
        c4gh_cli_error(&spec, "--to %g is before --from %g: no tick would be exported", e.to_s, e.from_s);
        return C4GH_CLI_EXIT_USAGE;
    }
    if ((e.moni != 0U) + e.json_lines + e.ticks > 1) {
        c4gh_cli_error(&spec, "--moni, --json-lines and --ticks exclude each other");
        return C4GH_CLI_EXIT_USAGE;
    }
    /* 1 MiB at a time: 4 KiB writes were a system call every 40 floats (glibc takes the
     * size only with a buffer given). The CSV has its own buffer, written unbuffered. */
    static char out_buf[1U << 20];
    static char csv_buf[1U << 20];
    e.csv = csv_buf;
    e.csv_cap = sizeof csv_buf;
    if (e.moni == 0U && !e.json_lines && !e.ticks) {
        (void)setvbuf(stdout, NULL, _IONBF, 0U);
    } else {
        (void)setvbuf(stdout, out_buf, _IOFBF, sizeof out_buf);
    }
    e.c.an.on_exchange = on_exchange;
    e.c.an.ctx = &e;
    if (c4gh_an_init(&a, &e.c.an) != 0) {
        fprintf(stderr, RP_TOOL ": out of memory\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    rc = rp_read(&a, argv[first], &file, !e.c.no_progress);
    c4gh_an_free(&a);
    csv_flush(&e);
    if (fflush(stdout) != 0 || e.write_failed || ferror(stdout)) {
        fprintf(stderr, RP_TOOL ": writing the export failed\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    return (rc == 2) ? RP_EXIT_UNREADABLE : (rc == 1 ? C4GH_CLI_EXIT_RUNTIME : C4GH_CLI_EXIT_OK);
}
