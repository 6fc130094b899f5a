/* SPDX-License-Identifier: MIT */
/* Table-driven command lines: see c4g_cli.h. */
#include "c4gh_cli.h"

#include "c4gh_textfile.h"
#include "c4gopen.h"

#include <errno.h>
#include <getopt.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define CLI_MAX_OPTS 96
#define CLI_HELP_KEY 0x10000
#define CLI_VERSION_KEY 0x10001

void c4gh_cli_error(const c4gh_cli_spec_t *spec, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", spec->tool);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void c4gh_cli_usage(const c4gh_cli_spec_t *spec, FILE *out)
{
    size_t i;
    fputs(spec->usage, out);
    fputs("\nOptions:\n", out);
    for (i = 0; i < spec->n_opts; i++) {
        const c4gh_cli_opt_t *o = &spec->opts[i];
        char left[64];
        if (o->help == NULL) {
            continue; /* an old spelling, kept for a release: not shown */
        }
        if (o->short_name != 0) {
            snprintf(left, sizeof left, "-%c, --%s%s%s", o->short_name, o->name,
                     o->arg != NULL ? " " : "", o->arg != NULL ? o->arg : "");
        } else {
            snprintf(left, sizeof left, "    --%s%s%s", o->name, o->arg != NULL ? " " : "",
                     o->arg != NULL ? o->arg : "");
        }
        if (strlen(left) > 28U) {
            fprintf(out, "  %s\n  %-28s %s\n", left, "", o->help);
        } else {
            fprintf(out, "  %-28s %s\n", left, o->help);
        }
    }
    fprintf(out, "  %-28s %s\n  %-28s %s\n", "-h, --help", "this text", "-V, --version",
            "version of the tool and of libc4gopen");
    if (spec->examples != NULL && spec->examples[0] != NULL) {
        fputs("\nExamples:\n", out);
        for (i = 0; spec->examples[i] != NULL; i++) {
            fprintf(out, "  %s\n", spec->examples[i]);
        }
    }
    if (spec->epilogue != NULL) {
        fprintf(out, "\n%s", spec->epilogue);
    }
}

/* Store one value as the row says; 0 or -1 with why filled. */
static int cli_store(void *ctx, const c4gh_cli_opt_t *o, const char *v, char *why, size_t whylen)
{
    c4gh_tf_num_t st = C4GH_TF_NUM_OK;
    switch (o->kind) {
    case C4GH_CLI_FLAG:
        *(int *)o->dest = 1;
        return 0;
    case C4GH_CLI_STRING:
        if (strlen(v) >= o->dest_cap) {
            snprintf(why, whylen, "longer than %u bytes", (unsigned)(o->dest_cap - 1U));
            return -1;
        }
        memcpy(o->dest, v, strlen(v) + 1U);
        return 0;
    case C4GH_CLI_INT: {
        long long x = 0;
        st = c4gh_tf_parse_int(v, (long long)o->lo, (long long)o->hi, &x);
        if (st == C4GH_TF_NUM_OK) {
            *(long long *)o->dest = x;
        }
        break;
    }
    case C4GH_CLI_UINT: {
        long long x = 0;
        st = c4gh_tf_parse_int(v, (long long)o->lo, (long long)o->hi, &x);
        if (st == C4GH_TF_NUM_OK) {
            *(unsigned *)o->dest = (unsigned)x;
        }
        break;
    }
    case C4GH_CLI_DOUBLE:
        st = c4gh_tf_parse_double(v, o->lo, o->hi, (double *)o->dest);
        break;
    case C4GH_CLI_CALL:
        return o->fn(ctx, o, v, why, whylen);
    default:
        snprintf(why, whylen, "option table row of unknown kind");
        return -1;
    }
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, v, o->lo, o->hi, why, whylen);
        return -1;
    }
    return 0;
}

/* The getopt tables, built from the rows; -1 when the table does not fit. */
static int cli_tables(const c4gh_cli_spec_t *spec, struct option *lo, char *so, size_t so_cap)
{
    size_t i, k = 0U;
    if (spec->n_opts + 3U > CLI_MAX_OPTS) {
        return -1;
    }
    if (!spec->permute) {
        so[k++] = '+'; /* POSIX order: stop at the first operand */
    }
    so[k++] = ':'; /* report a missing argument as ':' */
    for (i = 0; i < spec->n_opts; i++) {
        const c4gh_cli_opt_t *o = &spec->opts[i];
        lo[i].name = o->name;
        lo[i].has_arg = (o->arg != NULL) ? required_argument : no_argument;
        lo[i].flag = NULL;
        lo[i].val = (int)i + 1 + 0x100;
        if (o->short_name != 0 && k + 3U < so_cap) {
            so[k++] = (char)o->short_name;
            if (o->arg != NULL) {
                so[k++] = ':';
            }
        }
    }
    lo[i] = (struct option){"help", no_argument, NULL, CLI_HELP_KEY};
    lo[i + 1U] = (struct option){"version", no_argument, NULL, CLI_VERSION_KEY};
    lo[i + 2U] = (struct option){NULL, 0, NULL, 0};
    if (k + 3U >= so_cap) {
        return -1;
    }
    so[k++] = 'h';
    so[k++] = 'V';
    so[k] = '\0';
    return 0;
}

/* An old spelling (a row without help) is the row that stores where a shown one stores: the
 * note names the shown one. */
static void cli_old_spelling(const c4gh_cli_spec_t *spec, const c4gh_cli_opt_t *o)
{
    size_t i;
    for (i = 0; i < spec->n_opts; i++) {
        const c4gh_cli_opt_t *n = &spec->opts[i];
        if (n != o && n->help != NULL && n->kind == o->kind &&
            ((o->dest != NULL && n->dest == o->dest) || (o->dest == NULL && n->fn == o->fn))) {
            fprintf(stderr, "%s: --%s is spelt --%s now, as in the other tools (--%s is accepted until 3.0)\n",
                    spec->tool, o->name, n->name, o->name);
            return;
        }
    }
}

static const c4gh_cli_opt_t *cli_row_of(const c4gh_cli_spec_t *spec, int c)
{
    size_t i;
    if (c > 0x100 && (size_t)(c - 0x101) < spec->n_opts) {
        return &spec->opts[c - 0x101];
    }
    for (i = 0; i < spec->n_opts; i++) {
        if (spec->opts[i].short_name != 0 && spec->opts[i].short_name == c) {
            return &spec->opts[i];
        }
    }
    return NULL;
}

/* getopt's ':' (a value missing) or '?' (no such option), as one line. */
static void cli_getopt_error(const c4gh_cli_spec_t *spec, int c, char **argv, const char *help)
{
    char name[80];
    /* a short option (optopt set) may sit in a group ("-qZ"): name it alone */
    if (optopt != 0 && optopt < 0x100) {
        snprintf(name, sizeof name, "-%c", optopt);
    } else {
        c4gh_cli_path_text(argv[optind - 1], name, sizeof name);
    }
    if (c == ':') {
        c4gh_cli_error(spec, "option '%s' needs a value (see %s)", name, help);
    } else {
        c4gh_cli_error(spec, "unrecognized option '%s' (see %s)", name, help);
    }
}

c4gh_cli_result_t c4gh_cli_parse(const c4gh_cli_spec_t *spec, void *ctx, int argc, char **argv,
                       int *first_operand)
{
    struct option lo[CLI_MAX_OPTS];
    char so[2 * CLI_MAX_OPTS + 8];
    char help[96]; /* "TOOL [COMMAND] --help" */
    int c, n_operands;
    snprintf(help, sizeof help, "%s%s%s --help", spec->tool, spec->command != NULL ? " " : "",
             spec->command != NULL ? spec->command : "");
    if (cli_tables(spec, lo, so, sizeof so) != 0) {
        c4gh_cli_error(spec, "internal error: option table too large");
        return C4GH_CLI_BAD;
    }
    opterr = 0;
#if defined(__GLIBC__)
    optind = 0; /* glibc: a full restart, which re-reads the ordering ('+' or not) */
#else
    optind = 1;
#endif
    while ((c = getopt_long(argc, argv, so, lo, NULL)) != -1) {
        const c4gh_cli_opt_t *o;
        char why[300];
        if (c == 'h' || c == CLI_HELP_KEY) {
            c4gh_cli_usage(spec, stdout);
            return C4GH_CLI_DONE;
        }
        if (c == 'V' || c == CLI_VERSION_KEY) {
            printf("%s %s (libc4gopen %s%s%s)\n", spec->tool, C4G_VERSION_STRING,
                   C4G_VERSION_STRING, spec->version_extra != NULL ? ", " : "",
                   spec->version_extra != NULL ? spec->version_extra : "");
            return C4GH_CLI_DONE;
        }
        if (c == ':' || c == '?') {
            cli_getopt_error(spec, c, argv, help);
            return C4GH_CLI_BAD;
        }
        o = cli_row_of(spec, c);
        if (o == NULL) {
            c4gh_cli_error(spec, "unrecognized option '%s' (see %s)", argv[optind - 1], help);
            return C4GH_CLI_BAD;
        }
        why[0] = '\0';
        if (o->help == NULL) {
            cli_old_spelling(spec, o);
        }
        if (cli_store(ctx, o, o->arg != NULL ? optarg : NULL, why, sizeof why) != 0) {
            if (o->arg != NULL) {
                char shown[160];
                c4gh_cli_error(spec, "--%s: bad value '%s' (%s)", o->name,
                          c4gh_cli_path_text(optarg, shown, sizeof shown), why);
            } else {
                c4gh_cli_error(spec, "--%s: %s", o->name, why);
            }
            return C4GH_CLI_BAD;
        }
    }
    n_operands = argc - optind;
    if (n_operands < spec->operands_min ||
        (spec->operands_max >= 0 && n_operands > spec->operands_max)) {
        if (n_operands > 0 && spec->operands_max >= 0 && n_operands > spec->operands_max) {
            char arg[80];
            c4gh_cli_error(spec, "unexpected argument '%s' (see %s)",
                      c4gh_cli_path_text(argv[optind + spec->operands_max], arg, sizeof arg), help);
        } else {
            c4gh_cli_error(spec, "missing argument (see %s)", help);
        }
        return C4GH_CLI_BAD;
    }
    if (first_operand != NULL) {
        *first_operand = optind;
    }
    return C4GH_CLI_RUN;
}

const char *c4gh_cli_path_text(const char *path, char *out, size_t cap)
{
    c4gh_tf_escape(path, strlen(path), out, cap);
    return out;
}

void c4gh_cli_file_error(const char *tool, const char *opt, const char *path, int err)
{
    char p[600];
    c4gh_cli_path_text(path, p, sizeof p);
    if (opt != NULL && opt[0] != '\0') {
        fprintf(stderr, "%s: %s %s: %s\n", tool, opt, p, strerror(err));
    } else {
        fprintf(stderr, "%s: %s: %s\n", tool, p, strerror(err));
    }
}

int c4gh_cli_output_writable(const char *path)
{
    char dir[4096];
    const char *slash;
    struct stat st;
    if (strcmp(path, "-") == 0) {
        return 0;
    }
    if (path[0] == '\0') {
        errno = ENOENT;
        return -1;
    }
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            errno = EISDIR;
            return -1;
        }
        return access(path, W_OK) == 0 ? 0 : -1;
    }
    if (errno != ENOENT) {
        return -1; /* ENOTDIR, EACCES, ELOOP: the file cannot be made either */
    }
    slash = strrchr(path, '/');
    if (slash == NULL) {
        snprintf(dir, sizeof dir, ".");
    } else if (slash == path) {
        snprintf(dir, sizeof dir, "/");
    } else {
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    }
    if (stat(dir, &st) != 0) {
        return -1; /* errno: ENOENT, the directory is missing */
    }
    if (!S_ISDIR(st.st_mode)) {
        errno = ENOTDIR;
        return -1;
    }
    return access(dir, W_OK | X_OK) == 0 ? 0 : -1;
}

int c4gh_cli_check_output(const char *tool, const char *opt, const char *path)
{
    if (c4gh_cli_output_writable(path) != 0) {
        c4gh_cli_file_error(tool, opt, path, errno);
        return -1;
    }
    return 0;
}

FILE *c4gh_cli_open_output(const char *tool, const char *opt, const char *path, const char *mode)
{
    FILE *f;
    if (strcmp(path, "-") == 0) {
        return stdout;
    }
    f = fopen(path, mode);
    if (f == NULL) {
        c4gh_cli_file_error(tool, opt, path, errno);
    }
    return f;
}

int c4gh_cli_apply(const c4gh_cli_spec_t *spec, void *ctx, const char *name, const char *value, char *why,
              size_t whylen)
{
    size_t i, k;
    for (i = 0; i < spec->n_opts; i++) {
        const c4gh_cli_opt_t *o = &spec->opts[i];
        for (k = 0; o->name[k] != '\0' && name[k] != '\0'; k++) {
            const char a = (o->name[k] == '_') ? '-' : o->name[k];
            const char b = (name[k] == '_') ? '-' : name[k];
            if (a != b) {
                break;
            }
        }
        if (o->name[k] != '\0' || name[k] != '\0') {
            continue;
        }
        if (o->arg != NULL) {
            return cli_store(ctx, o, value, why, whylen) == 0 ? 0 : -1;
        }
        if (strcmp(value, "true") == 0 || strcmp(value, "yes") == 0 || strcmp(value, "on") == 0 ||
            strcmp(value, "1") == 0) {
            return cli_store(ctx, o, NULL, why, whylen) == 0 ? 0 : -1;
        }
        if (strcmp(value, "false") == 0 || strcmp(value, "no") == 0 || strcmp(value, "off") == 0 ||
            strcmp(value, "0") == 0) {
            return 0;
        }
        snprintf(why, whylen, "want true or false");
        return -1;
    }
    return 1;
}

const char *c4gh_cli_find_config(int argc, char **argv)
{
    int i;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0) {
            break;
        }
        if ((strcmp(argv[i], "-c") == 0 || strcmp(argv[i], "--config") == 0) && i + 1 < argc) {
            return argv[i + 1];
        }
        if (strncmp(argv[i], "--config=", 9) == 0) {
            return argv[i] + 9;
        }
    }
    return NULL;
}

int c4gh_cli_progress_wanted(void)
{
    return isatty(STDERR_FILENO);
}

void c4gh_cli_progress(const char *tool, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "\r%s: ", tool);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputs("\033[K", stderr);
    fflush(stderr);
}

void c4gh_cli_progress_end(void)
{
    fputs("\r\033[K", stderr);
    fflush(stderr);
}

int c4gh_cli_parse_axis_list(const char *text, unsigned max, uint32_t *bits)
{
    uint32_t out = 0U;
    const char *p = text;
    if (text == NULL || bits == NULL || max == 0U || max > 32U || *p == '\0') {
        return -1;
    }
    while (*p != '\0') {
        char item[24];
        const size_t n = strcspn(p, ",");
        long long lo = 0, hi = 0;
        char *dash;
        if (n == 0U || n >= sizeof item) {
            return -1;
        }
        memcpy(item, p, n);
        item[n] = '\0';
        dash = strchr(item, '-');
        if (dash != NULL) {
            *dash = '\0';
        }
        if (c4gh_tf_parse_int(item, 1, (long long)max, &lo) != C4GH_TF_NUM_OK ||
            (dash != NULL && c4gh_tf_parse_int(dash + 1, lo, (long long)max, &hi) != C4GH_TF_NUM_OK)) {
            return -1;
        }
        if (dash == NULL) {
            hi = lo;
        }
        for (; lo <= hi; lo++) {
            out |= 1U << (unsigned)(lo - 1);
        }
        p += n;
        if (*p == ',') {
            p++;
            if (*p == '\0') {
                return -1;
            }
        }
    }
    *bits = out;
    return 0;
}
