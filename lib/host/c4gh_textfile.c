/* SPDX-License-Identifier: MIT */
/* c4g_textfile: capped file loading, checked lines, strict numbers, INI via inih. */
#include "c4gh_textfile.h"

#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void c4gh_tf_open_mem(c4gh_tf_file_t *f, const char *path, const char *data, size_t len)
{
    memset(f, 0, sizeof *f);
    f->path = path;
    f->data = data;
    f->len = (data != NULL) ? len : 0U;
}

void c4gh_tf_free(c4gh_tf_file_t *f)
{
    free(f->owned);
    f->owned = NULL;
    f->data = NULL;
    f->len = 0U;
}

int c4gh_tf_load(c4gh_tf_file_t *f, const char *path, size_t max, char *err, size_t errlen)
{
    FILE *fp;
    struct stat st;
    char *buf;
    size_t n = 0U;
    size_t cap = 1U << 16;
    c4gh_tf_open_mem(f, path, NULL, 0U);
    fp = fopen(path, "rb");
    if (fp == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    if (fstat(fileno(fp), &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            fclose(fp);
            snprintf(err, errlen, "%s: is a directory, not a text file", path);
            return -1;
        }
        /* A regular file says its size: refuse a huge one without reading it. */
        if (S_ISREG(st.st_mode)) {
            if ((unsigned long long)st.st_size > (unsigned long long)max) {
                fclose(fp);
                snprintf(err, errlen, "%s: %llu bytes, more than the %zu-byte limit for this file: refused",
                         path, (unsigned long long)st.st_size, max);
                return -1;
            }
            cap = (size_t)st.st_size + 1U;
        }
    }
    if (cap > max + 1U) {
        cap = max + 1U;
    }
    buf = malloc(cap);
    for (;;) {
        size_t r;
        if (buf == NULL) {
            fclose(fp);
            snprintf(err, errlen, "%s: out of memory", path);
            return -1;
        }
        r = fread(buf + n, 1U, cap - n, fp);
        n += r;
        if (n > max) {
            /* A device or pipe (/dev/zero) has no size: stop at the cap. */
            free(buf);
            fclose(fp);
            snprintf(err, errlen, "%s: more than %zu bytes, the limit for this file: refused",
                     path, max);
            return -1;
        }
        if (r == 0U) {
            break;
        }
        if (n == cap) {
            size_t ncap = (cap > (max + 1U) / 2U) ? max + 1U : cap * 2U;
            char *nb = realloc(buf, ncap);
            if (nb == NULL) {
                free(buf);
            }
            buf = nb;
            cap = ncap;
        }
    }
    if (ferror(fp)) {
        int e = errno;
        free(buf);
        fclose(fp);
        snprintf(err, errlen, "%s: read error: %s", path, strerror(e));
        return -1;
    }
    fclose(fp);
    f->owned = buf;
    f->data = buf;
    f->len = n;
    return 0;
}

void c4gh_tf_escape(const char *s, size_t n, char *out, size_t cap)
{
    size_t o = 0U;
    size_t i;
    if (cap == 0U) {
        return;
    }
    for (i = 0U; i < n; i++) {
        const unsigned char c = (unsigned char)s[i];
        const size_t w = (c >= 0x20U && c < 0x7FU && c != '\\') ? 1U : 4U;
        if (o + w + 4U > cap) { /* room for "..." and the NUL */
            if (o + 4U <= cap) {
                memcpy(out + o, "...", 3U);
                o += 3U;
            }
            break;
        }
        if (w == 1U) {
            out[o++] = (char)c;
        } else {
            snprintf(out + o, cap - o, "\\x%02x", c);
            o += 4U;
        }
    }
    out[o] = '\0';
}

int c4gh_tf_error(const c4gh_tf_file_t *f, size_t col, char *err, size_t errlen, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (err == NULL || errlen == 0U) {
        return -1;
    }
    if (f->line == 0U) {
        snprintf(err, errlen, "%s: %s", f->path, msg);
    } else if (col == 0U) {
        snprintf(err, errlen, "%s:%u: %s", f->path, f->line, msg);
    } else {
        snprintf(err, errlen, "%s:%u:%zu: %s", f->path, f->line, col, msg);
    }
    return -1;
}

/* Length of the valid UTF-8 sequence at s (2..4), or 0 (RFC 3629: no overlong forms,
 * no surrogates, nothing above U+10FFFF). */
static size_t utf8_len(const unsigned char *s, size_t n)
{
    const unsigned c = s[0];
    unsigned lo = 0x80U;
    unsigned hi = 0xBFU;
    size_t need;
    size_t k;
    if (c >= 0xC2U && c <= 0xDFU) {
        need = 1U;
    } else if (c >= 0xE0U && c <= 0xEFU) {
        need = 2U;
        lo = (c == 0xE0U) ? 0xA0U : lo;
        hi = (c == 0xEDU) ? 0x9FU : hi;
    } else if (c >= 0xF0U && c <= 0xF4U) {
        need = 3U;
        lo = (c == 0xF0U) ? 0x90U : lo;
        hi = (c == 0xF4U) ? 0x8FU : hi;
    } else {
        return 0U;
    }
    if (n <= need || s[1] < lo || s[1] > hi) {
        return 0U;
    }
    for (k = 2U; k <= need; k++) {
        if ((s[k] & 0xC0U) != 0x80U) {
            return 0U;
        }
    }
    return need + 1U;
}

static int bad_byte(c4gh_tf_file_t *f, size_t i, const char *what, char *err, size_t errlen)
{
    const size_t from = (i - f->line_off > 24U) ? i - 24U : f->line_off;
    char ctx[128];
    if (i == f->line_off) {
        return c4gh_tf_error(f, 1U, err, errlen,
                        "%s \\x%02x at byte offset %zu: binary content is not accepted", what,
                        (unsigned char)f->data[i], i);
    }
    c4gh_tf_escape(f->data + from, i - from, ctx, sizeof ctx);
    return c4gh_tf_error(f, i - f->line_off + 1U, err, errlen,
                    "%s \\x%02x at byte offset %zu (after '%s%s'): binary content is not accepted",
                    what, (unsigned char)f->data[i], i, (from > f->line_off) ? "..." : "", ctx);
}

int c4gh_tf_next_line(c4gh_tf_file_t *f, char *out, size_t cap, char *err, size_t errlen)
{
    const unsigned char *d = (const unsigned char *)f->data;
    size_t i;
    size_t k = 0U;
    if (f->pos >= f->len || cap == 0U) {
        return 0;
    }
    f->line++;
    f->line_off = f->pos;
    for (i = f->pos; i < f->len && d[i] != '\n';) {
        const unsigned c = d[i];
        size_t w = 1U;
        if (c == '\r' && (i + 1U == f->len || d[i + 1U] == '\n')) {
            i++; /* CR LF line end */
            continue;
        }
        if (c == 0U) {
            return bad_byte(f, i, "NUL byte", err, errlen);
        }
        if ((c < 0x20U && c != '\t') || c == 0x7FU) {
            return bad_byte(f, i, "control byte", err, errlen);
        }
        if (c >= 0x80U) {
            w = utf8_len(d + i, f->len - i);
            if (w == 0U) {
                return bad_byte(f, i, "invalid UTF-8 byte", err, errlen);
            }
        }
        if (k + w >= cap) {
            return c4gh_tf_error(f, k + 1U, err, errlen,
                            "line longer than %zu bytes, the limit for this file", cap - 1U);
        }
        memcpy(out + k, d + i, w);
        k += w;
        i += w;
    }
    out[k] = '\0';
    f->pos = (i < f->len) ? i + 1U : i;
    return 1;
}

/* ---- numbers */

/* Digits of @p s from @p *i on; advances *i past them and returns how many. */
static size_t skip_digits(const char *s, size_t *i)
{
    size_t n = 0U;
    while (s[*i] >= '0' && s[*i] <= '9') {
        (*i)++;
        n++;
    }
    return n;
}

/* [+-]digits[.digits][e[+-]digits] (digits on at least one side of the point). */
static int decimal_syntax(const char *s, int allow_frac)
{
    size_t i = 0U;
    size_t mant;
    if (s[i] == '+' || s[i] == '-') {
        i++;
    }
    mant = skip_digits(s, &i);
    if (allow_frac && s[i] == '.') {
        i++;
        mant += skip_digits(s, &i);
    }
    if (mant == 0U) {
        return 0;
    }
    if (allow_frac && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (s[i] == '+' || s[i] == '-') {
            i++;
        }
        if (skip_digits(s, &i) == 0U) {
            return 0;
        }
    }
    return s[i] == '\0';
}

static int nonfinite_word(const char *s)
{
    static const char *const words[] = {"nan", "inf", "infinity"};
    size_t w;
    if (*s == '+' || *s == '-') {
        s++;
    }
    for (w = 0U; w < sizeof words / sizeof words[0]; w++) {
        size_t i;
        for (i = 0U; words[w][i] != '\0'; i++) {
            if ((s[i] | 0x20) != words[w][i]) {
                break;
            }
        }
        if (words[w][i] == '\0' && (s[i] == '\0' || s[i] == '(')) {
            return 1;
        }
    }
    return 0;
}

c4gh_tf_num_t c4gh_tf_parse_double(const char *s, double lo, double hi, double *out)
{
    double v;
    if (s == NULL || *s == '\0') {
        return C4GH_TF_NUM_EMPTY;
    }
    if (!decimal_syntax(s, 1)) {
        return nonfinite_word(s) ? C4GH_TF_NUM_NONFINITE : C4GH_TF_NUM_SYNTAX;
    }
    errno = 0;
    v = strtod(s, NULL);
    /* ERANGE: overflow (1e999) or a result too small to represent (1e-999). */
    if (errno == ERANGE || !isfinite(v) || v < lo || v > hi) {
        return C4GH_TF_NUM_RANGE;
    }
    *out = v;
    return C4GH_TF_NUM_OK;
}

c4gh_tf_num_t c4gh_tf_parse_int(const char *s, long long lo, long long hi, long long *out)
{
    long long v;
    if (s == NULL || *s == '\0') {
        return C4GH_TF_NUM_EMPTY;
    }
    if (!decimal_syntax(s, 0)) {
        if (decimal_syntax(s, 1)) {
            return C4GH_TF_NUM_NOT_INT;
        }
        return nonfinite_word(s) ? C4GH_TF_NUM_NONFINITE : C4GH_TF_NUM_SYNTAX;
    }
    errno = 0;
    v = strtoll(s, NULL, 10);
    if (errno == ERANGE || v < lo || v > hi) {
        return C4GH_TF_NUM_RANGE;
    }
    *out = v;
    return C4GH_TF_NUM_OK;
}

c4gh_tf_num_t c4gh_tf_parse_uint(const char *s, unsigned long long hi, unsigned long long *out)
{
    unsigned long long v;
    if (s == NULL || *s == '\0') {
        return C4GH_TF_NUM_EMPTY;
    }
    if (!decimal_syntax(s, 0)) {
        if (decimal_syntax(s, 1)) {
            return C4GH_TF_NUM_NOT_INT;
        }
        return nonfinite_word(s) ? C4GH_TF_NUM_NONFINITE : C4GH_TF_NUM_SYNTAX;
    }
    if (*s == '-') {
        return C4GH_TF_NUM_RANGE;
    }
    errno = 0;
    v = strtoull(s, NULL, 10);
    if (errno == ERANGE || v > hi) {
        return C4GH_TF_NUM_RANGE;
    }
    *out = v;
    return C4GH_TF_NUM_OK;
}

void c4gh_tf_num_explain(c4gh_tf_num_t st, const char *s, double lo, double hi, char *out, size_t cap)
{
    char v[80];
    c4gh_tf_escape(s != NULL ? s : "", s != NULL ? strlen(s) : 0U, v, sizeof v);
    switch (st) {
    case C4GH_TF_NUM_OK:
        snprintf(out, cap, "'%s' is fine", v);
        break;
    case C4GH_TF_NUM_EMPTY:
        snprintf(out, cap, "missing number");
        break;
    case C4GH_TF_NUM_NONFINITE:
        snprintf(out, cap, "'%s' is not a finite number", v);
        break;
    case C4GH_TF_NUM_RANGE:
        snprintf(out, cap, "'%s' is out of range %.15g..%.15g", v, lo, hi);
        break;
    case C4GH_TF_NUM_NOT_INT:
        snprintf(out, cap, "'%s' is not an integer", v);
        break;
    case C4GH_TF_NUM_SYNTAX:
    default:
        snprintf(out, cap, "'%s' is not a decimal number", v);
        break;
    }
}

/* ---- INI */

#define TF_INI_RAW 1024
#define TF_INI_MAX_SECTION 50 /* inih's MAX_SECTION: longer names would be cut silently */

typedef struct ini_ctx {
    c4gh_tf_file_t *f;
    c4gh_tf_ini_handler h;
    void *user;
    char raw[TF_INI_RAW];   /* the line last read, as in the file */
    size_t lead;            /* blanks dropped before giving it to inih */
    unsigned sect_line;     /* position of the current [section] header */
    size_t sect_col;
    unsigned fail_line;     /* line inih was on when this layer failed; 0 = none */
    char *err;
    size_t errlen;
} ini_ctx_t;

static char *ini_reader_fn(char *str, int num, void *stream)
{
    ini_ctx_t *x = stream;
    size_t cap = sizeof x->raw;
    size_t n;
    int r;
    if (x->fail_line != 0U || num < 3) {
        return NULL; /* stop at the first error */
    }
    /* inih's buffer holds num bytes: the line, its LF and the NUL must fit. */
    if ((size_t)num - 1U < cap) {
        cap = (size_t)num - 1U;
    }
    r = c4gh_tf_next_line(x->f, x->raw, cap, x->err, x->errlen);
    if (r < 0) {
        x->fail_line = x->f->line;
        return NULL;
    }
    if (r == 0) {
        return NULL;
    }
    x->lead = strspn(x->raw, " \t");
    if (x->raw[x->lead] == '[') {
        const char *end = strchr(x->raw + x->lead, ']');
        x->sect_line = x->f->line;
        x->sect_col = x->lead + 1U;
        if (end != NULL && (size_t)(end - (x->raw + x->lead) - 1) >= TF_INI_MAX_SECTION) {
            x->fail_line = x->f->line;
            c4gh_tf_error(x->f, x->lead + 1U, x->err, x->errlen,
                     "section name longer than %d characters", TF_INI_MAX_SECTION - 1);
            return NULL;
        }
    }
    n = strlen(x->raw + x->lead);
    memcpy(str, x->raw + x->lead, n);
    str[n] = '\n';
    str[n + 1U] = '\0';
    return str;
}

static int ini_handler_fn(void *user, const char *section, const char *name, const char *value)
{
    ini_ctx_t *x = user;
    char msg[400];
    size_t col = x->lead + 1U;
    unsigned line = x->f->line;
    c4gh_tf_ini_rc_t rc;
    if (x->fail_line != 0U) {
        return 1;
    }
    msg[0] = '\0';
    rc = x->h(x->user, section, name, value, msg, sizeof msg);
    if (rc == C4GH_TF_INI_OK) {
        return 1;
    }
    if (rc == C4GH_TF_INI_BAD_SECTION && x->sect_line != 0U) {
        line = x->sect_line;
        col = x->sect_col;
    } else if (rc == C4GH_TF_INI_BAD_VALUE) {
        /* inih splits at the first '=' or ':'; the value starts after the blanks. */
        const size_t sep = x->lead + strcspn(x->raw + x->lead, "=:");
        if (x->raw[sep] != '\0') {
            col = sep + 1U + strspn(x->raw + sep + 1U, " \t") + 1U;
        }
    }
    snprintf(x->err, x->errlen, "%s:%u:%zu: %s", x->f->path, line, col, msg);
    x->fail_line = x->f->line;
    return 0;
}

/* inih reported a syntax error on line n: say what the line was. */
static void ini_syntax_error(const c4gh_tf_file_t *f, unsigned n, char *err, size_t errlen)
{
    size_t i = 0U;
    size_t e;
    size_t lead;
    unsigned line = 1U;
    char text[100];
    while (line < n && i < f->len) {
        if (f->data[i++] == '\n') {
            line++;
        }
    }
    e = i;
    while (e < f->len && f->data[e] != '\n' && f->data[e] != '\r') {
        e++;
    }
    lead = i;
    while (lead < e && (f->data[lead] == ' ' || f->data[lead] == '\t')) {
        lead++;
    }
    c4gh_tf_escape(f->data + lead, e - lead, text, sizeof text);
    if (lead < e && f->data[lead] == '[') {
        snprintf(err, errlen, "%s:%u:%zu: '%s': a section header needs a closing ']'", f->path, n,
                 lead - i + 1U, text);
    } else {
        snprintf(err, errlen, "%s:%u:%zu: '%s': expected 'key = value', '[section]' or a ; or # comment",
                 f->path, n, lead - i + 1U, text);
    }
}

int c4gh_tf_ini_parse(c4gh_tf_file_t *f, c4gh_tf_ini_handler h, void *user, char *err, size_t errlen)
{
    ini_ctx_t x;
    int r;
    memset(&x, 0, sizeof x);
    x.f = f;
    x.h = h;
    x.user = user;
    x.err = err;
    x.errlen = errlen;
    if (errlen > 0U) {
        err[0] = '\0';
    }
    r = ini_parse_stream(ini_reader_fn, &x, ini_handler_fn, &x);
    /* inih returns the first line with an error. If that is not the line this layer
     * failed on, it is an earlier syntax error inih found by itself. */
    if (r > 0 && (unsigned)r != x.fail_line) {
        ini_syntax_error(f, (unsigned)r, err, errlen);
        return -1;
    }
    if (x.fail_line != 0U) {
        return -1;
    }
    if (r < 0) {
        snprintf(err, errlen, "%s: INI parser failed (%d)", f->path, r);
        return -1;
    }
    return 0;
}
