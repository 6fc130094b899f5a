/* SPDX-License-Identifier: MIT */
/* Table-driven command lines for every tool: one row per option gives its long and short
 * names, its argument, its help line and what it sets, so getopt_long's table, the --help
 * text and the value checks cannot drift apart. Errors follow one style on stderr:
 * "TOOL: --NAME: bad value 'VALUE' (WHY)". */
#ifndef C4GH_CLI_H
#define C4GH_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Exit codes shared by the tools. */
#define C4GH_CLI_EXIT_OK 0
#define C4GH_CLI_EXIT_RUNTIME 1 /* the job failed (controller error, socket, I/O) */
#define C4GH_CLI_EXIT_USAGE 2   /* bad command line or configuration */
/* Stopped by a signal (docs/cli.md, "Interrupting a tool"): SIGINT 128 + 2 in every tool, as
 * a shell reports an interrupted command; SIGTERM 128 + 15, but 0 in the two servers
 * (c4g-server, cell-sim), which a service manager stops with it. */
#define C4GH_CLI_EXIT_SIGINT 130
#define C4GH_CLI_EXIT_SIGTERM 143

typedef enum c4gh_cli_kind {
    C4GH_CLI_FLAG,   /* no argument: sets *(int *)dest to 1 */
    C4GH_CLI_STRING, /* copies the argument into (char *)dest of dest_cap bytes */
    C4GH_CLI_INT,    /* integer in [lo, hi] into *(long long *)dest */
    C4GH_CLI_UINT,   /* unsigned integer in [lo, hi] into *(unsigned *)dest */
    C4GH_CLI_DOUBLE, /* finite number in [lo, hi] into *(double *)dest */
    C4GH_CLI_CALL    /* calls fn(ctx, row, value); value is NULL for has_arg == 0 */
} c4gh_cli_kind_t;

struct c4gh_cli_opt;
/* A C4GH_CLI_CALL handler: 0 to go on; otherwise it wrote why into why (without the tool and
 * option names, which the caller adds). */
typedef int (*c4gh_cli_fn)(void *ctx, const struct c4gh_cli_opt *row, const char *value, char *why,
                      size_t whylen);

typedef struct c4gh_cli_opt {
    const char *name;  /* long name, without "--" */
    int short_name;    /* 0 for none */
    c4gh_cli_kind_t kind;
    const char *arg;   /* argument placeholder in --help (NULL: no argument) */
    const char *help;  /* one line; NULL: an old spelling kept for a release, not shown in
                        * --help, its use noted on stderr with the shown row's name (the row
                        * with the same dest, or for C4GH_CLI_CALL the same fn) */
    void *dest;        /* C4GH_CLI_FLAG/STRING/INT/UINT/DOUBLE */
    size_t dest_cap;   /* C4GH_CLI_STRING */
    double lo, hi;     /* C4GH_CLI_INT/UINT/DOUBLE */
    c4gh_cli_fn fn;         /* C4GH_CLI_CALL */
    int key;           /* free for the handler */
} c4gh_cli_opt_t;

typedef struct c4gh_cli_spec {
    const char *tool;             /* program name in messages */
    const char *version_extra;    /* appended to --version (may be NULL) */
    const char *usage;            /* "Usage: ..." line(s) and a one-paragraph summary */
    const c4gh_cli_opt_t *opts;
    size_t n_opts;
    const char *const *examples;  /* NULL-terminated, printed under "Examples:" */
    const char *epilogue;         /* printed last (may be NULL) */
    int operands_min, operands_max; /* non-option arguments allowed; max < 0: any */
    int permute;                  /* options may follow operands (GNU order; "--" ends them) */
    const char *command;          /* a subcommand: errors say "see TOOL COMMAND --help" */
} c4gh_cli_spec_t;

/* The outcome of c4gh_cli_parse: go on, stop with exit code 0 (--help/--version printed),
 * or stop with C4GH_CLI_EXIT_USAGE (the error is already on stderr). */
typedef enum c4gh_cli_result { C4GH_CLI_RUN = 0, C4GH_CLI_DONE = 1, C4GH_CLI_BAD = 2 } c4gh_cli_result_t;

/* Parse argv against the table. --help and --version are built in (-h, -V). On C4GH_CLI_RUN
 * *first_operand is the index of the first non-option argument. getopt stops at the first
 * operand (POSIX order), so options after it are operands, unless spec->permute (then
 * argv is reordered so the operands come last). */
c4gh_cli_result_t c4gh_cli_parse(const c4gh_cli_spec_t *spec, void *ctx, int argc, char **argv,
                       int *first_operand);

/* The --help text. */
void c4gh_cli_usage(const c4gh_cli_spec_t *spec, FILE *out);

/* One error line on stderr in the shared style: "TOOL: MESSAGE". */
void c4gh_cli_error(const c4gh_cli_spec_t *spec, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* One setting by its long option name, as an INI file gives it ('_' and '-' alike), stored
 * as the command line would store it; a flag takes true/false (yes/no, on/off, 1/0; false
 * leaves it unset). 0 stored, 1 no such option, -1 a bad value (why says what is wrong). */
int c4gh_cli_apply(const c4gh_cli_spec_t *spec, void *ctx, const char *name, const char *value, char *why,
              size_t whylen);

/* The value of "-c FILE" / "--config FILE" / "--config=FILE" in argv before a "--", or NULL:
 * a tool that reads its options from a file reads it before the command line (the command
 * line wins). */
const char *c4gh_cli_find_config(int argc, char **argv);

/* ---- file names in messages and output files checked at start-up ---- */

/* A path as messages show it: printable ASCII as is, any other byte as \xNN (cut with
 * "..." to fit cap). Returns out. */
const char *c4gh_cli_path_text(const char *path, char *out, size_t cap);

/* An axis list like "1,3-5" (numbers 1..@p max, @p max <= 32, ranges ascending, no empty
 * item) into bit i-1 of @p bits. Returns 0, or -1 with @p bits untouched. */
int c4gh_cli_parse_axis_list(const char *text, unsigned max, uint32_t *bits);

/* One error line about a file, naming it once with the system's reason:
 * "TOOL: OPT PATH: strerror(err)" (OPT may be NULL or "": "TOOL: PATH: reason"). */
void c4gh_cli_file_error(const char *tool, const char *opt, const char *path, int err);

/* An output file written later (at exit or by another thread): fails now when it could not
 * be written then: its directory is missing or not writable, or the path is a directory
 * or a file without write permission. "-" (stdout) always passes. 0, or -1 with errno set
 * and nothing printed. */
int c4gh_cli_output_writable(const char *path);

/* c4gh_cli_output_writable, and c4gh_cli_file_error when it fails; 0 or -1. */
int c4gh_cli_check_output(const char *tool, const char *opt, const char *path);

/* fopen(path, mode) for an output file; "-" is stdout. On failure c4gh_cli_file_error and NULL. */
FILE *c4gh_cli_open_output(const char *tool, const char *opt, const char *path, const char *mode);

/* ---- a progress line for long runs: on stderr, and only when stderr is a terminal ---- */

/* 1 when stderr is a terminal (a progress line would be seen, not logged). */
int c4gh_cli_progress_wanted(void);

/* Redraw the progress line in place: "\rTOOL: TEXT" and the rest of the line erased. */
void c4gh_cli_progress(const char *tool, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Erase the progress line (before the summary or any other output). */
void c4gh_cli_progress_end(void);

#endif
