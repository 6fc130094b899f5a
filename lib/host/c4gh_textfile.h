/* SPDX-License-Identifier: MIT */
/* c4g_textfile: what the tools' file parsers share (scenario, trajectory, feedforward,
 * INI). Files are read whole into memory with a size cap, handed out line by line with
 * the checks every parser needs (line length, NUL and other binary bytes, invalid
 * UTF-8), and numbers are parsed strictly (whole token, decimal, finite, in range).
 * Every error names PATH:LINE:COLUMN and shows offending bytes escaped as \xNN. */
#ifndef C4GH_TEXTFILE_H
#define C4GH_TEXTFILE_H

#include <stddef.h>

typedef struct c4gh_tf_file {
    const char *path;       /* for messages */
    const char *data;       /* the bytes (not NUL-terminated) */
    size_t len;
    size_t pos;             /* next byte to read */
    unsigned line;          /* 1-based number of the line last returned; 0 before */
    size_t line_off;        /* byte offset of that line's first byte */
    char *owned;            /* what c4gh_tf_load allocated, freed by c4gh_tf_free */
} c4gh_tf_file_t;

/* Read the file at @p path into memory, refusing more than @p max bytes: a regular file
 * by its size, anything else (a pipe, /dev/zero) after max bytes. 0, or -1 with "PATH:
 * ..." in @p err. */
int c4gh_tf_load(c4gh_tf_file_t *f, const char *path, size_t max, char *err, size_t errlen);
/* The same parser input over a buffer already in memory (tests, fuzz targets). */
void c4gh_tf_open_mem(c4gh_tf_file_t *f, const char *path, const char *data, size_t len);
void c4gh_tf_free(c4gh_tf_file_t *f);

/* The next line, without its LF (and a CR before it), NUL-terminated in @p out.
 * 1 = a line, 0 = end of input, -1 = error in @p err ("PATH:LINE:COL: ..."): a line
 * of @p cap bytes or more, a NUL or other control byte (TAB is text), invalid UTF-8. */
int c4gh_tf_next_line(c4gh_tf_file_t *f, char *out, size_t cap, char *err, size_t errlen);

/* "PATH:LINE:COL: " + the message, for the line last returned (COL 1-based; 0 leaves it
 * out). Returns -1 so that parsers can `return c4gh_tf_error(...)`. */
int c4gh_tf_error(const c4gh_tf_file_t *f, size_t col, char *err, size_t errlen, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Printable copy of n bytes: printable ASCII as is, anything else (and backslash) as
 * \xNN; cut with "..." to fit @p cap. */
void c4gh_tf_escape(const char *s, size_t n, char *out, size_t cap);

typedef enum c4gh_tf_num {
    C4GH_TF_NUM_OK = 0,
    C4GH_TF_NUM_EMPTY,       /* nothing there */
    C4GH_TF_NUM_SYNTAX,      /* not decimal number text ("abc", "0x10", "1,5") */
    C4GH_TF_NUM_NONFINITE,   /* "nan", "inf", "infinity" */
    C4GH_TF_NUM_RANGE,       /* outside lo..hi, or not representable (1e999, 1e-999) */
    C4GH_TF_NUM_NOT_INT      /* a fraction or exponent where an integer is wanted */
} c4gh_tf_num_t;

/* Decimal [+-]digits[.digits][e[+-]digits], the whole string, finite, lo <= v <= hi.
 * *out is written only on C4GH_TF_NUM_OK. */
c4gh_tf_num_t c4gh_tf_parse_double(const char *s, double lo, double hi, double *out);
/* Decimal [+-]digits, the whole string, lo <= v <= hi. */
c4gh_tf_num_t c4gh_tf_parse_int(const char *s, long long lo, long long hi, long long *out);
/* Decimal [+]digits up to @p hi (e.g. a 64-bit seed). */
c4gh_tf_num_t c4gh_tf_parse_uint(const char *s, unsigned long long hi, unsigned long long *out);
/* Why @p s was refused: "'1e39' is out of range -1000000..1000000". */
void c4gh_tf_num_explain(c4gh_tf_num_t st, const char *s, double lo, double hi, char *out, size_t cap);

/* ---- INI files through inih, with the same line checks and correct positions */

typedef enum c4gh_tf_ini_rc {
    C4GH_TF_INI_OK = 0,
    C4GH_TF_INI_BAD_SECTION,  /* error reported at the [section] line */
    C4GH_TF_INI_BAD_KEY,      /* error reported at the key's column */
    C4GH_TF_INI_BAD_VALUE     /* error reported at the value's column */
} c4gh_tf_ini_rc_t;

/* One key = value. On an error, write the message (without position) into @p msg. */
typedef c4gh_tf_ini_rc_t (*c4gh_tf_ini_handler)(void *user, const char *section, const char *name,
                                      const char *value, char *msg, size_t msglen);

/* Parse @p f as INI: inih does the syntax, this layer feeds it checked lines (no line
 * is ever split, leading blanks are dropped so an indented key is a key and never a
 * continuation line) and stops at the first error. 0, or -1 with
 * "PATH:LINE:COL: ..." in @p err. */
int c4gh_tf_ini_parse(c4gh_tf_file_t *f, c4gh_tf_ini_handler h, void *user, char *err, size_t errlen);

/* Size caps used by the tools (bytes). */
#define C4GH_TF_MAX_INI (1U << 20)
#define C4GH_TF_MAX_SCENARIO (1U << 20)

#endif /* C4GH_TEXTFILE_H */
