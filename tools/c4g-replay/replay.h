/* SPDX-License-Identifier: MIT */
/* c4g-replay: the commands and what they share (reading files through the analysis,
 * the common options, the report). */
#ifndef C4G_REPLAY_H
#define C4G_REPLAY_H

#include "c4gh_analyze.h"
#include "c4gh_cli.h"
#include "c4gh_capture.h"

#include <stdio.h>

#define RP_TOOL "c4g-replay"

/* Exit codes: the tools' shared ones, and for check: */
#define RP_EXIT_FINDINGS 1   /* the captures show findings (check) */
#define RP_EXIT_UNREADABLE 2 /* an input could not be read (also bad usage) */
#define RP_EXIT_NO_SESSION 3 /* check: a file holds no C4G Open session (nothing was checked) */

/* What reading one file found. */
typedef struct rp_file {
    const char *path;
    int opened;               /* 0: not a readable capture (fatal[] says why) */
    int complete;             /* read to its end */
    char format[8];
    char link[16];
    int nano;
    c4gh_cap_counts_t n;
    uint64_t doubled;         /* frames captured twice (analysed once) */
    char first_bad[400];      /* the first damaged frame, in words */
    char fatal[400];           /* why reading stopped early, or why it could not start */
} rp_file_t;

/* Options of the analysing commands. */
typedef struct rp_common {
    c4gh_an_options_t an;
    int json;
    int quiet;
    int no_progress;
} rp_common_t;

void rp_common_default(rp_common_t *c);
/* C4GH_CLI_CALL handlers for the shared rows (ctx is the rp_common_t) */
int rp_opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen);
int rp_opt_tcycle1(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen);
int rp_opt_num_policy(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen);

/* Read @p path through the analysis @p a (which must outlive the file names). Errors go to
 * stderr as "c4g-replay: ...". Returns 0 when the file was read to its end (damaged frames
 * are counted and reported, not fatal), 1 when it stopped early, 2 when it could not be
 * opened. */
int rp_read(c4gh_an_t *a, const char *path, rp_file_t *info, int progress);

/* Reports (report.c) */
void rp_report_text(FILE *out, const c4gh_an_t *a, const rp_file_t *files, unsigned n_files,
                    uint32_t allow);
int rp_report_json(FILE *out, const c4gh_an_t *a, const rp_file_t *files, unsigned n_files,
                   uint32_t allow);
/* One line per finding (check): returns the number of findings not waived. */
unsigned rp_report_findings(FILE *out, const c4gh_an_t *a, const rp_file_t *files, unsigned n_files,
                            uint32_t allow);
/* Sessions of the file read as @p path (by the analysis' file name). */
unsigned rp_file_sessions(const c4gh_an_t *a, const char *path);
/* "no C4G Open session found (...)": what a file without a session held. */
const char *rp_no_session_text(const c4gh_an_t *a, const rp_file_t *f, char *buf, size_t cap);
/* Findings not waived, damaged files counted. */
unsigned rp_count_findings(const c4gh_an_t *a, const rp_file_t *files, unsigned n_files, uint32_t allow);

/* live (live.c): what its command line asks of c4g-sim --capture. */
typedef struct rp_live {
    const char *path;
    char host[256];
    unsigned port;            /* 0: no --to */
    double speed;             /* 0: not given */
    int topspeed;
    unsigned loops;           /* 0: not given */
    unsigned gap_ms;
    unsigned session;         /* 0: not given */
    unsigned spin_us;
    double tolerance;
    const char *t_cycle1, *policy, *ports; /* as written; NULL: not given */
    int json;
} rp_live_t;

#define RP_LIVE_ARGS 40       /* c4g-sim's argv, NULL included */
#define RP_LIVE_NUMS 8        /* numbers written for it */
#define RP_LIVE_NUM 32

/* c4g-sim's argv for @p L (argv[0] = @p sim, NULL-terminated; numbers written into @p num,
 * which must outlive argv): the argument count, or -1 when @p cap is too small. */
int rp_live_argv(const rp_live_t *L, const char *sim, char **argv, size_t cap, char (*num)[RP_LIVE_NUM]);

/* Run tool @p name beside this executable (a build tree, an installed prefix), else on
 * PATH, with @p argv (argv[0] is overwritten, NULL-terminated). Returns only when it could
 * not be run (errno says why). */
void rp_exec_tool(const char *name, char **argv);
/* The front ends' argv: one more argument, kept NULL-terminated; an option and its value
 * (NULL: the option alone). 0, or -1 when @p cap is too small. */
int rp_argv_put(char **argv, size_t cap, size_t *n, const char *s);
int rp_argv_put_opt(char **argv, size_t cap, size_t *n, const char *opt, const char *value);
/* --port LIST checked as the analysing commands check it (passed on as written). */
int rp_check_port(const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen);

/* rerun (rerun.c): what its command line asks of c4g-server --replay-rerun --capture. */
typedef struct rp_rerun {
    const char *path;
    int echo;                 /* --behaviour echo */
    unsigned session;         /* 0: not given */
    double tolerance;
    long long list;
    const char *ports;        /* as written; NULL: not given */
    int json, no_progress;
    char **srv_argv;          /* c4g-server's own options (after "--") */
    int srv_argc;
} rp_rerun_t;

#define RP_RERUN_MAX_SERVER_ARGS 128
#define RP_RERUN_ARGS (RP_RERUN_MAX_SERVER_ARGS + 24) /* c4g-server's argv, NULL included */
#define RP_RERUN_NUMS 4       /* numbers written for it */

/* c4g-server's argv for @p R (argv[0] = @p srv, NULL-terminated; numbers written into @p num,
 * which must outlive argv): the argument count, or -1 when @p cap is too small. */
int rp_rerun_argv(const rp_rerun_t *R, const char *srv, char **argv, size_t cap, char (*num)[RP_LIVE_NUM]);

/* Commands: argv[0] is the command's name. */
int rp_cmd_summary(int argc, char **argv);
int rp_cmd_check(int argc, char **argv);
int rp_cmd_export(int argc, char **argv);
int rp_cmd_rerun(int argc, char **argv);
int rp_cmd_live(int argc, char **argv);
int rp_cmd_plot(int argc, char **argv);
int rp_cmd_follow(int argc, char **argv);

#endif
