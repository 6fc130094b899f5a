/* SPDX-License-Identifier: MIT */
/* Table-driven command lines for every tool: one row per option gives its long and short
 * names, its argument, its help line and what it sets, so getopt_long's table, the --help
 * text and the value checks cannot drift apart. Errors follow one style on stderr:
 * "TOOL: --NAME: bad value 'VALUE' (WHY)". */
#ifndef C4G_CLI_H
#define C4G_CLI_H

#include <stddef.h>
#include <stdio.h>

/* Exit codes shared by the tools. */
#define CLI_EXIT_OK 0
#define CLI_EXIT_RUNTIME 1 /* the job failed (controller error, socket, I/O) */
#define CLI_EXIT_USAGE 2   /* bad command line or configuration */

typedef enum cli_kind {
    CLI_FLAG,   /* no argument: sets *(int *)dest to 1 */
    CLI_STRING, /* copies the argument into (char *)dest of dest_cap bytes */
    CLI_INT,    /* integer in [lo, hi] into *(long long *)dest */
    CLI_UINT,   /* unsigned integer in [lo, hi] into *(unsigned *)dest */
    CLI_DOUBLE, /* finite number in [lo, hi] into *(double *)dest */
    CLI_CALL    /* calls fn(ctx, row, value); value is NULL for has_arg == 0 */
} cli_kind_t;

struct cli_opt;
/* A CLI_CALL handler: 0 to go on; otherwise it wrote why into why (without the tool and
 * option names, which the caller adds). */
typedef int (*cli_fn)(void *ctx, const struct cli_opt *row, const char *value, char *why,
                      size_t whylen);

typedef struct cli_opt {
    const char *name;  /* long name, without "--" */
    int short_name;    /* 0 for none */
    cli_kind_t kind;
    const char *arg;   /* argument placeholder in --help (NULL: no argument) */
    const char *help;  /* one line */
    void *dest;        /* CLI_FLAG/STRING/INT/UINT/DOUBLE */
    size_t dest_cap;   /* CLI_STRING */
    double lo, hi;     /* CLI_INT/UINT/DOUBLE */
    cli_fn fn;         /* CLI_CALL */
    int key;           /* free for the handler */
} cli_opt_t;

typedef struct cli_spec {
    const char *tool;             /* program name in messages */
    const char *version_extra;    /* appended to --version (may be NULL) */
    const char *usage;            /* "Usage: ..." line(s) and a one-paragraph summary */
    const cli_opt_t *opts;
    size_t n_opts;
    const char *const *examples;  /* NULL-terminated, printed under "Examples:" */
    const char *epilogue;         /* printed last (may be NULL) */
    int operands_min, operands_max; /* non-option arguments allowed; max < 0: any */
    int permute;                  /* options may follow operands (GNU order; "--" ends them) */
    const char *command;          /* a subcommand: errors say "see TOOL COMMAND --help" */
} cli_spec_t;

/* The outcome of cli_parse: go on, stop with exit code 0 (--help/--version printed),
 * or stop with CLI_EXIT_USAGE (the error is already on stderr). */
typedef enum cli_result { CLI_RUN = 0, CLI_DONE = 1, CLI_BAD = 2 } cli_result_t;

/* Parse argv against the table. --help and --version are built in (-h, -V). On CLI_RUN
 * *first_operand is the index of the first non-option argument. getopt stops at the first
 * operand (POSIX order), so options after it are operands, unless spec->permute (then
 * argv is reordered so the operands come last). */
cli_result_t cli_parse(const cli_spec_t *spec, void *ctx, int argc, char **argv,
                       int *first_operand);

/* The --help text. */
void cli_usage(const cli_spec_t *spec, FILE *out);

/* One error line on stderr in the shared style: "TOOL: MESSAGE". */
void cli_error(const cli_spec_t *spec, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* One setting by its long option name, as an INI file gives it ('_' and '-' alike), stored
 * as the command line would store it; a flag takes true/false (yes/no, on/off, 1/0; false
 * leaves it unset). 0 stored, 1 no such option, -1 a bad value (why says what is wrong). */
int cli_apply(const cli_spec_t *spec, void *ctx, const char *name, const char *value, char *why,
              size_t whylen);

/* The value of "-c FILE" / "--config FILE" / "--config=FILE" in argv before a "--", or NULL:
 * a tool that reads its options from a file reads it before the command line (the command
 * line wins). */
const char *cli_find_config(int argc, char **argv);

/* ---- file names in messages and output files checked at start-up ---- */

/* A path as messages show it: printable ASCII as is, any other byte as \xNN (cut with
 * "..." to fit cap). Returns out. */
const char *cli_path_text(const char *path, char *out, size_t cap);

/* One error line about a file, naming it once with the system's reason:
 * "TOOL: OPT PATH: strerror(err)" (OPT may be NULL or "": "TOOL: PATH: reason"). */
void cli_file_error(const char *tool, const char *opt, const char *path, int err);

/* An output file written later (at exit or by another thread): fails now when it could not
 * be written then: its directory is missing or not writable, or the path is a directory
 * or a file without write permission. "-" (stdout) always passes. 0, or -1 with errno set
 * and nothing printed. */
int cli_output_writable(const char *path);

/* cli_output_writable, and cli_file_error when it fails; 0 or -1. */
int cli_check_output(const char *tool, const char *opt, const char *path);

/* fopen(path, mode) for an output file; "-" is stdout. On failure cli_file_error and NULL. */
FILE *cli_open_output(const char *tool, const char *opt, const char *path, const char *mode);

/* ---- a progress line for long runs: on stderr, and only when stderr is a terminal ---- */

/* 1 when stderr is a terminal (a progress line would be seen, not logged). */
int cli_progress_wanted(void);

/* Redraw the progress line in place: "\rTOOL: TEXT" and the rest of the line erased. */
void cli_progress(const char *tool, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Erase the progress line (before the summary or any other output). */
void cli_progress_end(void);

#endif
