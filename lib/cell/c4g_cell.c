/* SPDX-License-Identifier: MIT */
/* Cell protocol codec: fixed-width fields, instructions, replies, status texts. */
#include "c4gopen.h"
#include <float.h>
#include <string.h>

#define CRLF_LEN 2U
#define HEAD_LEN 3U
#define REPLY_HEAD_LEN 2U
#define SCALE_MM 1000.0
#define SCALE_RAD 10000.0
#define ACTION_OPEN_LEN 4U
#define ACTION_CLOSE_LEN 5U

/* Layout of one field: total width and index of '.', 0 when there is none. */
typedef struct {
    size_t width;
    size_t point;
    int32_t max;
} field_fmt_t;

static const field_fmt_t k_fmt_mm = {C4G_CELL_FIELD_LEN, 4U, C4G_CELL_COUNTS_MAX};
static const field_fmt_t k_fmt_rad = {C4G_CELL_FIELD_LEN, 3U, C4G_CELL_COUNTS_MAX};
static const field_fmt_t k_fmt_int = {C4G_CELL_INT_LEN, 0U, C4G_CELL_INT_MAX};

/* The command table (C4G_CELL_COMMANDS in c4gopen_cell.h) as the codec uses it. */
typedef struct {
    const char *head;
    size_t head_len;
    c4g_cell_args_t args;
    int32_t lo;
    int32_t hi;
    c4g_cell_reply_kind_t reply;
    uint32_t devices;
} cmd_row_t;

/* Deviation D-05 (MISRA 2.5): the row macro is used, as the argument of the table. */
/* cppcheck-suppress misra-c2012-2.5 */
#define CELL_X_ROW(cmd, head, args, lo, hi, reply, devices, words, arg, what, help) \
    {(head), sizeof(head) - 1U, (args), (lo), (hi), (reply), (devices)},
static const cmd_row_t k_cmds[C4G_CELL_CMD_COUNT_] = {C4G_CELL_COMMANDS(CELL_X_ROW)};

static const char k_open[ACTION_OPEN_LEN] = {'O', 'P', 'E', 'N'};
static const char k_close[ACTION_CLOSE_LEN] = {'C', 'L', 'O', 'S', 'E'};

const char *c4g_cell_error_text(int32_t code, int *project)
{
    const char *text = "unknown error number";
    int proj = 0;
    switch (code) {
    case C4G_CELL_E_NONE: text = "no error"; break;
    case C4G_CELL_E_GENERIC: text = "generic error"; break;
    case C4G_CELL_E_SERVO1: text = "servo motor 1 error"; break;
    case C4G_CELL_E_SERVO2: text = "servo motor 2 error"; break;
    case C4G_CELL_E_UNKNOWN_CMD: text = "unknown instruction"; proj = 1; break;
    case C4G_CELL_E_MALFORMED: text = "malformed instruction"; proj = 1; break;
    case C4G_CELL_E_RANGE: text = "value out of range"; proj = 1; break;
    case C4G_CELL_E_SERVO_OFF: text = "servo is off"; proj = 1; break;
    case C4G_CELL_E_WORKSPACE: text = "target outside the workspace"; proj = 1; break;
    case C4G_CELL_E_UNSUPPORTED: text = "instruction not handled by this device"; proj = 1; break;
    case C4G_CELL_E_BUSY: text = "motion in progress"; proj = 1; break;
    default: break;
    }
    if (project != NULL) {
        *project = proj;
    }
    return text;
}

const char *c4g_cell_cmd_name(c4g_cell_cmd_t cmd)
{
    const char *name = "???";
    if ((uint32_t)cmd < (uint32_t)C4G_CELL_CMD_COUNT_) {
        name = k_cmds[cmd].head;
    }
    return name;
}

c4g_status_t c4g_cell_cmd_info(c4g_cell_cmd_t cmd, c4g_cell_cmd_info_t *out)
{
    c4g_status_t st = C4G_OK;
    if (out == NULL) {
        st = C4G_ERR_NULL;
    } else if ((uint32_t)cmd >= (uint32_t)C4G_CELL_CMD_COUNT_) {
        st = C4G_ERR_ARG;
    } else {
        const cmd_row_t *row = &k_cmds[cmd];
        out->cmd = cmd;
        out->head = row->head;
        out->head_len = row->head_len;
        out->args = row->args;
        out->lo = row->lo;
        out->hi = row->hi;
        out->reply = row->reply;
        out->devices = row->devices;
    }
    return st;
}

/* ------------------------------------------------------------------ values */

static const field_fmt_t *fmt_of(c4g_cell_unit_t unit)
{
    const field_fmt_t *f = NULL;
    switch (unit) {
    case C4G_CELL_UNIT_MM: f = &k_fmt_mm; break;
    case C4G_CELL_UNIT_RAD: f = &k_fmt_rad; break;
    case C4G_CELL_UNIT_INT: f = &k_fmt_int; break;
    default: break;
    }
    return f;
}

static int in_range(int32_t v, const field_fmt_t *f)
{
    return ((v <= f->max) && (v >= -f->max)) ? 1 : 0;
}

c4g_status_t c4g_cell_from_double(double value, c4g_cell_unit_t unit, int32_t *out)
{
    c4g_status_t st = C4G_OK;
    const field_fmt_t *f = fmt_of(unit);
    if (out == NULL) {
        st = C4G_ERR_NULL;
    } else if (f == NULL) {
        st = C4G_ERR_ARG;
    } else if (!((value >= -DBL_MAX) && (value <= DBL_MAX))) {
        /* NaN fails every comparison, infinities fail the bounds (no libm) */
        st = C4G_ERR_NONFINITE;
    } else {
        double scale = 1.0;
        if (unit == C4G_CELL_UNIT_MM) {
            scale = SCALE_MM;
        } else if (unit == C4G_CELL_UNIT_RAD) {
            scale = SCALE_RAD;
        } else {
            /* integer: counts are units */
        }
        const double x = value * scale;
        /* Range test before the conversion: converting an out-of-range double is UB. */
        const double lim = (double)f->max + 0.5;
        if ((x >= lim) || (x <= -lim)) {
            st = C4G_ERR_RANGE;
        } else if (x >= 0.0) {
            const double r = x + 0.5; /* truncating x + 0.5: halves go up */
            *out = (int32_t)r;
        } else {
            const double r = 0.5 - x; /* |x| + 0.5: halves go away from zero */
            *out = -(int32_t)r;
        }
    }
    return st;
}

c4g_status_t c4g_cell_to_double(int32_t counts, c4g_cell_unit_t unit, double *out)
{
    c4g_status_t st = C4G_OK;
    const field_fmt_t *f = fmt_of(unit);
    if (out == NULL) {
        st = C4G_ERR_NULL;
    } else if (f == NULL) {
        st = C4G_ERR_ARG;
    } else if (in_range(counts, f) == 0) {
        st = C4G_ERR_RANGE;
    } else if (unit == C4G_CELL_UNIT_MM) {
        *out = (double)counts / SCALE_MM;
    } else if (unit == C4G_CELL_UNIT_RAD) {
        *out = (double)counts / SCALE_RAD;
    } else {
        *out = (double)counts;
    }
    return st;
}

/* Write the field into dst (f->width chars); counts already range-checked. */
static void put_field(int32_t counts, const field_fmt_t *f, char *dst)
{
    static const char k_digits[10] = {'0', '1', '2', '3', '4', '5', '6', '7', '8', '9'};
    uint32_t mag = (counts < 0) ? (uint32_t)(-counts) : (uint32_t)counts;
    size_t i = f->width;
    dst[0] = (counts < 0) ? '-' : '+';
    while (i > 1U) {
        i--;
        if ((f->point != 0U) && (i == f->point)) {
            dst[i] = '.';
        } else {
            dst[i] = k_digits[mag % 10U];
            mag /= 10U;
        }
    }
}

c4g_status_t c4g_cell_field_encode(int32_t counts, c4g_cell_unit_t unit, char *buf,
                                        size_t cap, size_t *out_len)
{
    c4g_status_t st = C4G_OK;
    const field_fmt_t *f = fmt_of(unit);
    if ((buf == NULL) || (out_len == NULL)) {
        st = C4G_ERR_NULL;
    } else if (f == NULL) {
        st = C4G_ERR_ARG;
    } else if (in_range(counts, f) == 0) {
        st = C4G_ERR_RANGE;
    } else if (cap < f->width) {
        st = C4G_ERR_CAPACITY;
    } else {
        put_field(counts, f, buf);
        *out_len = f->width;
    }
    return st;
}

/* ------------------------------------------------------------------ parsing */

/* A parse cursor over one line body (the line without its CR LF). */
typedef struct {
    const char *s;
    size_t body;  /* body length */
    size_t pos;   /* next char to read */
    c4g_cell_diag_t *diag;
} cursor_t;

static c4g_status_t fail_at(const cursor_t *c, c4g_status_t st, size_t index,
                                 c4g_cell_part_t part, int32_t axis)
{
    if (c->diag != NULL) {
        c->diag->status = st;
        c->diag->column = (uint32_t)index + 1U;
        c->diag->part = part;
        c->diag->axis = axis;
    }
    return st;
}

/* Lines end in CR LF with no other CR or LF: sets c->body. */
static c4g_status_t check_terminator(cursor_t *c, size_t len)
{
    c4g_status_t st = C4G_OK;
    size_t i = 0U;
    size_t bad = len; /* index of the first CR or LF, len if none */
    const char *s = c->s;
    while ((i < len) && (bad == len)) {
        if ((s[i] == '\r') || (s[i] == '\n')) {
            bad = i;
        }
        i++;
    }
    if (len == 0U) {
        st = fail_at(c, C4G_ERR_LENGTH, 0U, C4G_CELL_PART_LENGTH, -1);
    } else if (((bad + CRLF_LEN) == len) && (s[bad] == '\r') && (s[bad + 1U] == '\n')) {
        c->body = bad;
    } else if (((bad + 1U) == len) && (s[bad] == '\r')) {
        st = fail_at(c, C4G_ERR_CELL_TERMINATOR, len, C4G_CELL_PART_TERMINATOR, -1);
    } else {
        st = fail_at(c, C4G_ERR_CELL_TERMINATOR, bad, C4G_CELL_PART_TERMINATOR, -1);
    }
    return st;
}

/* Need n more chars in the body. */
static c4g_status_t need(const cursor_t *c, size_t n, c4g_cell_part_t part, int32_t axis)
{
    c4g_status_t st = C4G_OK;
    if ((c->body - c->pos) < n) {
        st = fail_at(c, C4G_ERR_LENGTH, c->body, part, axis);
    }
    return st;
}

/* The body must end here. */
static c4g_status_t expect_end(const cursor_t *c)
{
    c4g_status_t st = C4G_OK;
    if (c->pos != c->body) {
        st = fail_at(c, C4G_ERR_LENGTH, c->pos, C4G_CELL_PART_LENGTH, -1);
    }
    return st;
}

static char cur_char(const cursor_t *c)
{
    const char *s = c->s;
    return s[c->pos];
}

static int char_differs(char a, char b)
{
    return (a != b) ? 1 : 0;
}

static int is_digit(char ch)
{
    return ((ch >= '0') && (ch <= '9')) ? 1 : 0;
}

/* Parse the field at s[0..f->width); *bad gets the offending index and part. */
static c4g_status_t parse_field(const char *s, const field_fmt_t *f, int32_t *out,
                                     size_t *bad)
{
    c4g_status_t st = C4G_OK;
    int32_t v = 0;
    size_t i = 1U;
    if ((s[0] != '+') && (s[0] != '-')) {
        st = C4G_ERR_CELL_SIGN;
        *bad = 0U;
    }
    while ((st == C4G_OK) && (i < f->width)) {
        if ((f->point != 0U) && (i == f->point)) {
            if (s[i] != '.') {
                st = C4G_ERR_CELL_POINT;
                *bad = i;
            }
        } else if (is_digit(s[i]) == 0) {
            st = C4G_ERR_CELL_DIGIT;
            *bad = i;
        } else {
            v = (v * 10) + ((int32_t)s[i] - (int32_t)'0');
        }
        i++;
    }
    if (st == C4G_OK) {
        *out = (s[0] == '-') ? -v : v;
    }
    return st;
}

static c4g_status_t take_field(cursor_t *c, const field_fmt_t *f, c4g_cell_part_t part,
                                    int32_t axis, int32_t *out)
{
    c4g_status_t st = need(c, f->width, part, axis);
    if (st == C4G_OK) {
        size_t bad = 0U;
        st = parse_field(&c->s[c->pos], f, out, &bad);
        if (st != C4G_OK) {
            st = fail_at(c, st, c->pos + bad, part, axis);
        } else {
            c->pos += f->width;
        }
    }
    return st;
}

c4g_status_t c4g_cell_field_decode(const char *buf, size_t len, c4g_cell_unit_t unit,
                                        int32_t *out, c4g_cell_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    const field_fmt_t *f = fmt_of(unit);
    if ((buf == NULL) || (out == NULL)) {
        st = C4G_ERR_NULL;
    } else if (f == NULL) {
        st = C4G_ERR_ARG;
    } else {
        cursor_t c = {buf, len, 0U, diag};
        int32_t v = 0;
        st = take_field(&c, f, C4G_CELL_PART_VALUE, -1, &v);
        if (st == C4G_OK) {
            st = expect_end(&c);
        }
        if (st == C4G_OK) {
            *out = v;
        }
    }
    return st;
}

static c4g_status_t take_flag(cursor_t *c, uint8_t *out)
{
    c4g_status_t st = need(c, 1U, C4G_CELL_PART_FLAG, -1);
    if (st == C4G_OK) {
        const char ch = cur_char(c);
        if (ch == 'T') {
            *out = 1U;
        } else if (ch == 'F') {
            *out = 0U;
        } else {
            st = fail_at(c, C4G_ERR_CELL_FLAG, c->pos, C4G_CELL_PART_FLAG, -1);
        }
        c->pos++;
    }
    return st;
}

/* Robot layout X Y Z [mm] C [rad]; platform A B [rad]. */
static const field_fmt_t *axis_fmt(uint32_t n_axes, uint32_t axis)
{
    return ((n_axes == C4G_CELL_AXES_ROBOT) && (axis < 3U)) ? &k_fmt_mm : &k_fmt_rad;
}

static c4g_status_t take_pose(cursor_t *c, uint32_t n_axes, c4g_cell_pose_t *pose)
{
    c4g_status_t st = C4G_OK;
    uint32_t a = 0U;
    pose->n_axes = n_axes;
    while ((st == C4G_OK) && (a < n_axes)) {
        st = take_field(c, axis_fmt(n_axes, a), C4G_CELL_PART_AXIS, (int32_t)a, &pose->v[a]);
        a++;
    }
    return st;
}

/* Integer field with a lower and upper semantic bound. */
static c4g_status_t take_int(cursor_t *c, int32_t lo, int32_t hi, int32_t *out)
{
    const size_t at = c->pos;
    c4g_status_t st = take_field(c, &k_fmt_int, C4G_CELL_PART_VALUE, -1, out);
    if ((st == C4G_OK) && ((*out < lo) || (*out > hi))) {
        st = fail_at(c, C4G_ERR_RANGE, at, C4G_CELL_PART_VALUE, -1);
    }
    return st;
}

/* Match the fixed word w (n chars) at the cursor; mismatch -> st_bad. */
static c4g_status_t take_word(cursor_t *c, const char *w, size_t n, c4g_status_t st_bad,
                                   c4g_cell_part_t part)
{
    c4g_status_t st = C4G_OK;
    size_t i = 0U;
    while ((st == C4G_OK) && (i < n)) {
        if (c->pos >= c->body) {
            st = fail_at(c, C4G_ERR_LENGTH, c->body, part, -1);
        } else if (char_differs(cur_char(c), w[i]) != 0) {
            st = fail_at(c, st_bad, c->pos, part, -1);
        } else {
            c->pos++;
        }
        i++;
    }
    return st;
}

/* How many chars of row's head the body at the cursor matches. */
static size_t head_match(const cursor_t *c, const cmd_row_t *row)
{
    const size_t avail = c->body - c->pos;
    const char *s = &c->s[c->pos];
    const char *h = row->head;
    size_t m = 0U;
    while ((m < row->head_len) && (m < avail) && (char_differs(s[m], h[m]) == 0)) {
        m++;
    }
    return m;
}

/* The row whose whole head starts the body. Errors point at the first char no head
   continues with: column 1 when no head shares the first three chars (the spec's
   head), else the char after the longest partial match (LENGTH when the line ends). */
static c4g_status_t find_head(cursor_t *c, c4g_cell_cmd_t *cmd)
{
    c4g_status_t st = need(c, HEAD_LEN, C4G_CELL_PART_HEAD, -1);
    if (st == C4G_OK) {
        uint32_t k = 0U;
        uint32_t found = (uint32_t)C4G_CELL_CMD_COUNT_;
        size_t best = 0U;
        while ((k < (uint32_t)C4G_CELL_CMD_COUNT_) && (found == (uint32_t)C4G_CELL_CMD_COUNT_)) {
            const size_t m = head_match(c, &k_cmds[k]);
            if (m == k_cmds[k].head_len) {
                found = k;
            } else if (m > best) {
                best = m;
            } else {
                /* a shorter partial match: keep the best */
            }
            k++;
        }
        if (found != (uint32_t)C4G_CELL_CMD_COUNT_) {
            *cmd = (c4g_cell_cmd_t)found;
            c->pos += k_cmds[found].head_len;
        } else if (best < HEAD_LEN) {
            st = fail_at(c, C4G_ERR_CELL_HEAD, c->pos, C4G_CELL_PART_HEAD, -1);
        } else if ((c->pos + best) == c->body) {
            st = fail_at(c, C4G_ERR_LENGTH, c->body, C4G_CELL_PART_HEAD, -1);
        } else {
            st = fail_at(c, C4G_ERR_CELL_HEAD, c->pos + best, C4G_CELL_PART_HEAD, -1);
        }
    }
    return st;
}

static c4g_status_t take_action(cursor_t *c, uint8_t *open)
{
    c4g_status_t st = need(c, 1U, C4G_CELL_PART_ACTION, -1);
    if (st == C4G_OK) {
        const char ch = cur_char(c);
        if (ch == 'O') {
            *open = 1U;
            st = take_word(c, k_open, ACTION_OPEN_LEN, C4G_ERR_CELL_ACTION, C4G_CELL_PART_ACTION);
        } else if (ch == 'C') {
            *open = 0U;
            st = take_word(c, k_close, ACTION_CLOSE_LEN, C4G_ERR_CELL_ACTION,
                           C4G_CELL_PART_ACTION);
        } else {
            st = fail_at(c, C4G_ERR_CELL_ACTION, c->pos, C4G_CELL_PART_ACTION, -1);
        }
    }
    return st;
}

static c4g_status_t take_mov(cursor_t *c, c4g_cell_instr_t *out)
{
    c4g_status_t st = need(c, 1U, C4G_CELL_PART_MODE, -1);
    if (st == C4G_OK) {
        const char ch = cur_char(c);
        if (ch == 'A') {
            out->relative = 0U;
        } else if (ch == 'R') {
            out->relative = 1U;
        } else {
            st = fail_at(c, C4G_ERR_CELL_MODE, c->pos, C4G_CELL_PART_MODE, -1);
        }
        c->pos++;
    }
    if (st == C4G_OK) {
        /* The body length picks the layout: robot 36, platform 20; the midpoint
           splits malformed lines so the column points at the real problem. */
        uint32_t n = C4G_CELL_AXES_PLATFORM;
        if (c->body > 28U) {
            n = C4G_CELL_AXES_ROBOT;
        }
        st = take_pose(c, n, &out->pose);
    }
    return st;
}

/* The arguments of row's layout. */
static c4g_status_t take_args(cursor_t *c, const cmd_row_t *row, c4g_cell_instr_t *out)
{
    c4g_status_t st = C4G_OK;
    switch (row->args) {
    case C4G_CELL_ARGS_INT:
        st = take_int(c, row->lo, row->hi, &out->value);
        break;
    case C4G_CELL_ARGS_INT_ACTION:
        st = take_int(c, row->lo, row->hi, &out->value);
        if (st == C4G_OK) {
            st = take_action(c, &out->open);
        }
        break;
    case C4G_CELL_ARGS_MODE_POSE:
        st = take_mov(c, out);
        break;
    case C4G_CELL_ARGS_CLEAR_POSE:
        st = take_field(c, &k_fmt_mm, C4G_CELL_PART_VALUE, -1, &out->clearance);
        if (st == C4G_OK) {
            st = take_pose(c, C4G_CELL_AXES_ROBOT, &out->pose);
        }
        break;
    case C4G_CELL_ARGS_NONE:
    default:
        break; /* no data */
    }
    return st;
}

static c4g_status_t decode_instr_body(cursor_t *c, c4g_cell_instr_t *out)
{
    c4g_cell_cmd_t cmd = C4G_CELL_CMD_STA;
    c4g_status_t st = find_head(c, &cmd);
    if (st == C4G_OK) {
        st = take_args(c, &k_cmds[cmd], out);
    }
    if (st == C4G_OK) {
        st = expect_end(c);
    }
    if (st == C4G_OK) {
        out->cmd = cmd;
    }
    return st;
}

c4g_status_t c4g_cell_instr_decode(const char *line, size_t len, c4g_cell_instr_t *out,
                                        c4g_cell_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    if ((line == NULL) || (out == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        cursor_t c = {line, 0U, 0U, diag};
        (void)memset(out, 0, sizeof *out);
        st = check_terminator(&c, len);
        if (st == C4G_OK) {
            st = decode_instr_body(&c, out);
        }
        if (st != C4G_OK) {
            (void)memset(out, 0, sizeof *out);
        }
    }
    return st;
}

/* "OK" followed by the status data: robot body 48, platform 32. */
static c4g_status_t take_sta(cursor_t *c, c4g_cell_reply_t *out)
{
    /* The midpoint picks the layout, so a malformed line's column is meaningful. */
    uint32_t n = C4G_CELL_AXES_PLATFORM;
    c4g_status_t st;
    if (c->body > 40U) {
        n = C4G_CELL_AXES_ROBOT;
    }
    out->kind = C4G_CELL_REPLY_STA;
    st = take_flag(c, &out->moving);
    if (st == C4G_OK) {
        st = take_pose(c, n, &out->pose);
    }
    if (st == C4G_OK) {
        st = take_flag(c, &out->servo_on);
    }
    if (st == C4G_OK) {
        st = take_int(c, 0, C4G_CELL_OVR_MAX, &out->override_pct);
    }
    if (st == C4G_OK) {
        st = take_int(c, -C4G_CELL_INT_MAX, C4G_CELL_INT_MAX, &out->error);
    }
    return st;
}

static c4g_status_t decode_reply_body(cursor_t *c, c4g_cell_reply_t *out)
{
    c4g_status_t st = need(c, REPLY_HEAD_LEN, C4G_CELL_PART_HEAD, -1);
    if (st == C4G_OK) {
        const char h0 = c->s[0];
        const char h1 = c->s[1];
        c->pos = REPLY_HEAD_LEN;
        if ((h0 == 'E') && (h1 == 'R')) {
            out->kind = C4G_CELL_REPLY_ER;
            st = take_int(c, -C4G_CELL_INT_MAX, C4G_CELL_INT_MAX, &out->error);
        } else if ((h0 == 'O') && (h1 == 'K')) {
            if (c->body == REPLY_HEAD_LEN) {
                out->kind = C4G_CELL_REPLY_OK;
            } else {
                st = take_sta(c, out);
            }
        } else if ((h0 == 'O') || (h0 == 'E')) {
            st = fail_at(c, C4G_ERR_CELL_HEAD, 1U, C4G_CELL_PART_HEAD, -1);
        } else {
            st = fail_at(c, C4G_ERR_CELL_HEAD, 0U, C4G_CELL_PART_HEAD, -1);
        }
    }
    if (st == C4G_OK) {
        st = expect_end(c);
    }
    return st;
}

c4g_status_t c4g_cell_reply_decode(const char *line, size_t len, c4g_cell_reply_t *out,
                                        c4g_cell_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    if ((line == NULL) || (out == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        cursor_t c = {line, 0U, 0U, diag};
        (void)memset(out, 0, sizeof *out);
        st = check_terminator(&c, len);
        if (st == C4G_OK) {
            st = decode_reply_body(&c, out);
        }
        if (st != C4G_OK) {
            (void)memset(out, 0, sizeof *out);
        }
    }
    return st;
}

/* ------------------------------------------------------------------ encoding */

/* A bounded writer into a local line buffer (lines never exceed C4G_CELL_LINE_MAX). */
typedef struct {
    char b[C4G_CELL_LINE_MAX];
    size_t n;
} writer_t;

static void w_chars(writer_t *w, const char *s, size_t n)
{
    (void)memcpy(&w->b[w->n], s, n);
    w->n += n;
}

static void w_char(writer_t *w, char ch)
{
    w->b[w->n] = ch;
    w->n++;
}

static c4g_status_t w_field(writer_t *w, int32_t v, const field_fmt_t *f)
{
    c4g_status_t st = C4G_OK;
    if (in_range(v, f) == 0) {
        st = C4G_ERR_RANGE;
    } else {
        put_field(v, f, &w->b[w->n]);
        w->n += f->width;
    }
    return st;
}

static c4g_status_t w_pose(writer_t *w, const c4g_cell_pose_t *p)
{
    c4g_status_t st = C4G_OK;
    uint32_t a = 0U;
    if ((p->n_axes != C4G_CELL_AXES_ROBOT) && (p->n_axes != C4G_CELL_AXES_PLATFORM)) {
        st = C4G_ERR_AXES;
    }
    while ((st == C4G_OK) && (a < p->n_axes)) {
        st = w_field(w, p->v[a], axis_fmt(p->n_axes, a));
        a++;
    }
    return st;
}

static c4g_status_t w_int(writer_t *w, int32_t v, int32_t lo, int32_t hi)
{
    c4g_status_t st = C4G_ERR_RANGE;
    if ((v >= lo) && (v <= hi)) {
        st = w_field(w, v, &k_fmt_int);
    }
    return st;
}

static c4g_status_t w_flush(const writer_t *w, c4g_status_t st_in, char *buf, size_t cap,
                                 size_t *out_len)
{
    c4g_status_t st = st_in;
    if (st == C4G_OK) {
        if (cap < (w->n + CRLF_LEN)) {
            st = C4G_ERR_CAPACITY;
        } else {
            (void)memcpy(buf, w->b, w->n);
            buf[w->n] = '\r';
            buf[w->n + 1U] = '\n';
            *out_len = w->n + CRLF_LEN;
        }
    }
    return st;
}

static c4g_status_t encode_instr_data(const c4g_cell_instr_t *in, const cmd_row_t *row,
                                           writer_t *w)
{
    c4g_status_t st = C4G_OK;
    switch (row->args) {
    case C4G_CELL_ARGS_INT:
        st = w_int(w, in->value, row->lo, row->hi);
        break;
    case C4G_CELL_ARGS_INT_ACTION:
        st = w_int(w, in->value, row->lo, row->hi);
        if (in->open != 0U) {
            w_chars(w, k_open, ACTION_OPEN_LEN);
        } else {
            w_chars(w, k_close, ACTION_CLOSE_LEN);
        }
        break;
    case C4G_CELL_ARGS_MODE_POSE:
        w_char(w, (in->relative != 0U) ? 'R' : 'A');
        st = w_pose(w, &in->pose);
        break;
    case C4G_CELL_ARGS_CLEAR_POSE:
        st = w_field(w, in->clearance, &k_fmt_mm);
        if ((st == C4G_OK) && (in->pose.n_axes != C4G_CELL_AXES_ROBOT)) {
            st = C4G_ERR_AXES;
        }
        if (st == C4G_OK) {
            st = w_pose(w, &in->pose);
        }
        break;
    case C4G_CELL_ARGS_NONE:
    default:
        break; /* no data */
    }
    return st;
}

c4g_status_t c4g_cell_instr_encode(const c4g_cell_instr_t *in, char *buf, size_t cap,
                                        size_t *out_len)
{
    c4g_status_t st = C4G_OK;
    if ((in == NULL) || (buf == NULL) || (out_len == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((uint32_t)in->cmd >= (uint32_t)C4G_CELL_CMD_COUNT_) {
        st = C4G_ERR_ARG;
    } else {
        writer_t w;
        w.n = 0U;
        const cmd_row_t *row = &k_cmds[in->cmd];
        w_chars(&w, row->head, row->head_len);
        st = w_flush(&w, encode_instr_data(in, row, &w), buf, cap, out_len);
    }
    return st;
}

c4g_status_t c4g_cell_reply_encode(const c4g_cell_reply_t *in, char *buf, size_t cap,
                                        size_t *out_len)
{
    c4g_status_t st = C4G_OK;
    if ((in == NULL) || (buf == NULL) || (out_len == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        writer_t w;
        w.n = 0U;
        switch (in->kind) {
        case C4G_CELL_REPLY_OK:
            w_chars(&w, "OK", REPLY_HEAD_LEN);
            break;
        case C4G_CELL_REPLY_ER:
            w_chars(&w, "ER", REPLY_HEAD_LEN);
            st = w_int(&w, in->error, -C4G_CELL_INT_MAX, C4G_CELL_INT_MAX);
            break;
        case C4G_CELL_REPLY_STA:
            w_chars(&w, "OK", REPLY_HEAD_LEN);
            w_char(&w, (in->moving != 0U) ? 'T' : 'F');
            st = w_pose(&w, &in->pose);
            if (st == C4G_OK) {
                w_char(&w, (in->servo_on != 0U) ? 'T' : 'F');
                st = w_int(&w, in->override_pct, 0, C4G_CELL_OVR_MAX);
            }
            if (st == C4G_OK) {
                st = w_int(&w, in->error, -C4G_CELL_INT_MAX, C4G_CELL_INT_MAX);
            }
            break;
        default:
            st = C4G_ERR_ARG;
            break;
        }
        st = w_flush(&w, st, buf, cap, out_len);
    }
    return st;
}

/* ------------------------------------------------------------------ decimal text */

/* Decimal text scanner state: magnitude in counts plus the rounding digit. */
typedef struct {
    size_t places;      /* decimals kept: MM 3, RAD 4, INT 0 */
    size_t frac;        /* fraction digits seen */
    uint32_t digits;    /* digits seen in total */
    uint32_t point;     /* '.' seen */
    uint32_t round_up;  /* first dropped digit >= 5 */
    uint32_t over;      /* integer part beyond the field */
    int32_t mag;
    int32_t max;
} dec_t;

/* Saturating mag * 10 + d: once beyond max the value is only "too large". */
static int32_t dec_push(int32_t mag, int32_t d, int32_t max)
{
    int32_t r = mag;
    if (mag <= max) {
        r = (mag * 10) + d;
    }
    return r;
}

static void dec_digit(dec_t *t, int32_t d)
{
    t->digits++;
    if (t->point == 0U) {
        if (t->mag > t->max) {
            t->over = 1U; /* keep scanning: a syntax error still wins */
        }
        t->mag = dec_push(t->mag, d, t->max);
    } else if (t->frac < t->places) {
        t->mag = dec_push(t->mag, d, t->max);
        t->frac++;
    } else if (t->frac == t->places) {
        if (d >= 5) {
            t->round_up = 1U;
        }
        t->frac++;
    } else {
        /* later digits cannot change a half-away-from-zero rounding */
    }
}

static c4g_status_t dec_scan(const char *s, size_t len, size_t start, dec_t *t)
{
    c4g_status_t st = C4G_OK;
    size_t i = start;
    while ((st == C4G_OK) && (i < len)) {
        const char ch = s[i];
        if ((ch == '.') && (t->point == 0U)) {
            t->point = 1U;
        } else if (is_digit(ch) == 0) {
            st = C4G_ERR_CELL_DIGIT;
        } else {
            dec_digit(t, (int32_t)ch - (int32_t)'0');
        }
        i++;
    }
    if ((st == C4G_OK) && (t->digits == 0U)) {
        st = C4G_ERR_CELL_DIGIT;
    }
    while ((st == C4G_OK) && (t->frac < t->places)) {
        t->mag = dec_push(t->mag, 0, t->max);
        t->frac++;
    }
    return st;
}

c4g_status_t c4g_cell_from_text(const char *s, size_t len, c4g_cell_unit_t unit,
                                     int32_t *out)
{
    c4g_status_t st = C4G_OK;
    const field_fmt_t *f = fmt_of(unit);
    if ((s == NULL) || (out == NULL)) {
        st = C4G_ERR_NULL;
    } else if (f == NULL) {
        st = C4G_ERR_ARG;
    } else if (len == 0U) {
        st = C4G_ERR_LENGTH;
    } else {
        dec_t t;
        size_t start = 0U;
        uint32_t neg = 0U;
        (void)memset(&t, 0, sizeof t);
        t.max = f->max;
        if (f->point != 0U) {
            t.places = f->width - f->point - 1U;
        }
        if (s[0] == '-') {
            neg = 1U;
            start = 1U;
        } else if (s[0] == '+') {
            start = 1U;
        } else {
            /* unsigned: starts with a digit or '.' */
        }
        st = dec_scan(s, len, start, &t);
        if (st == C4G_OK) {
            const int32_t mag = t.mag + (int32_t)t.round_up;
            if ((t.over != 0U) || (mag > t.max)) {
                st = C4G_ERR_RANGE;
            } else {
                *out = (neg != 0U) ? -mag : mag;
            }
        }
    }
    return st;
}
