/* SPDX-License-Identifier: MIT */
/* Reading a capture through the analysis, with a progress bar on a terminal. */
#include "replay.h"

#include "c4gh_textfile.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define RP_PROGRESS_MIN_BYTES (16U << 20) /* smaller files are read in a blink */

void rp_common_default(rp_common_t *c)
{
    memset(c, 0, sizeof *c);
    c4gh_an_options_default(&c->an);
}

/* --port LIST: comma-separated PC ports; replaces the defaults 1000,1001. */
int rp_opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_common_t *c = ctx;
    const char *p = v;
    (void)row;
    c->an.n_ports = 0U;
    while (*p != '\0') {
        char item[16];
        size_t n = strcspn(p, ",");
        long long port = 0;
        if (n == 0U || n >= sizeof item) {
            (void)snprintf(why, whylen, "want ports 1..65535 separated by commas");
            return -1;
        }
        memcpy(item, p, n);
        item[n] = '\0';
        if (c4gh_tf_parse_int(item, 1, 65535, &port) != C4GH_TF_NUM_OK) {
            (void)snprintf(why, whylen, "'%s' is not a port 1..65535", item);
            return -1;
        }
        if (c->an.n_ports >= C4GH_AN_MAX_PORTS) {
            (void)snprintf(why, whylen, "at most %u ports", C4GH_AN_MAX_PORTS);
            return -1;
        }
        c->an.ports[c->an.n_ports++] = (uint16_t)port;
        p += n;
        if (*p == ',') {
            p++;
        }
    }
    if (c->an.n_ports == 0U) {
        (void)snprintf(why, whylen, "no port given");
        return -1;
    }
    return 0;
}

int rp_opt_tcycle1(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_common_t *c = ctx;
    long long us = 0;
    c4gh_tf_num_t st = c4gh_tf_parse_int(v, 1, 1000000, &us);
    (void)row;
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, v, 1, 1000000, why, whylen);
        return -1;
    }
    c->an.t_cycle1_ns = (uint64_t)us * 1000U;
    return 0;
}

/* --num-policy: the controller's reply NUM rule, when the capture cannot tell it (a PC that
 * answers under the other rule looks consistent on its own). */
int rp_opt_num_policy(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_common_t *c = ctx;
    (void)row;
    if (strcmp(v, "auto") == 0) {
        c->an.num_policy = C4G_NUM_EITHER;
    } else if (strcmp(v, "plus-one") == 0) {
        c->an.num_policy = C4G_NUM_PLUS_ONE;
    } else if (strcmp(v, "echo") == 0) {
        c->an.num_policy = C4G_NUM_ECHO;
    } else {
        (void)snprintf(why, whylen, "want auto, plus-one or echo");
        return -1;
    }
    return 0;
}

static void progress(const c4gh_cap_t *c, int final)
{
    const uint64_t size = c4gh_cap_size(c), pos = c4gh_cap_pos(c);
    const unsigned pct = (size > 0U) ? (unsigned)((pos * 100U) / size) : 0U;
    if (final) {
        fprintf(stderr, "\r%-72s\r", "");
    } else {
        fprintf(stderr, "\r" RP_TOOL ": %.40s %3u%% (%.1f of %.1f MB)", c4gh_cap_path(c), pct,
                (double)pos / 1e6, (double)size / 1e6);
    }
    fflush(stderr);
}

int rp_read(c4gh_an_t *a, const char *path, rp_file_t *info, int want_progress)
{
    char err[390];
    c4gh_cap_t *c;
    c4gh_cap_pkt_t p;
    int rc = 0;
    uint64_t doubled0;
    const int show = want_progress && isatty(2);
    memset(info, 0, sizeof *info);
    info->path = path;
    c = c4gh_cap_open(path, err, sizeof err);
    if (c == NULL) {
        fprintf(stderr, RP_TOOL ": %s\n", err);
        (void)snprintf(info->fatal, sizeof info->fatal, "%s", err);
        return 2;
    }
    info->opened = 1;
    (void)snprintf(info->format, sizeof info->format, "%s", c4gh_cap_format(c));
    (void)snprintf(info->link, sizeof info->link, "%s", c4gh_cap_link_name(c));
    info->nano = c4gh_cap_nanosecond(c);
    doubled0 = a->doubled;
    for (;;) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, err, sizeof err);
        if (r == C4GH_CAP_END) {
            break;
        }
        if (r == C4GH_CAP_FATAL) {
            fprintf(stderr, RP_TOOL ": %s\n", err);
            (void)snprintf(info->fatal, sizeof info->fatal, "%s", err);
            rc = 1;
            break;
        }
        if (r == C4GH_CAP_BAD) {
            if (info->first_bad[0] == '\0') {
                (void)snprintf(info->first_bad, sizeof info->first_bad, "%s", err);
            }
            if (c4gh_cap_counts(c)->bad <= 10U) {
                fprintf(stderr, RP_TOOL ": %s\n", err);
            }
            continue;
        }
        if (r == C4GH_CAP_DATAGRAM) {
            c4gh_an_datagram(a, path, &p);
        }
        if (show && c4gh_cap_size(c) >= RP_PROGRESS_MIN_BYTES && (c4gh_cap_counts(c)->frames & 0xFFFFU) == 0U) {
            progress(c, 0);
        }
    }
    if (show && c4gh_cap_size(c) >= RP_PROGRESS_MIN_BYTES) {
        progress(c, 1);
    }
    if (c4gh_cap_counts(c)->bad > 10U) {
        fprintf(stderr, RP_TOOL ": %s: %llu damaged frames in all (the first 10 shown)\n", path,
                (unsigned long long)c4gh_cap_counts(c)->bad);
    }
    info->n = *c4gh_cap_counts(c);
    info->complete = (rc == 0);
    c4gh_an_file_end(a, path);
    info->doubled = a->doubled - doubled0;
    c4gh_cap_close(c);
    return rc;
}
