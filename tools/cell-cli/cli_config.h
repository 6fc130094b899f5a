/* SPDX-License-Identifier: MIT */
/* cell-cli INI configuration file (-c FILE, $CELL_CLI_CONFIG, ~/.config/cell-cli.ini). */
#ifndef CLI_CONFIG_H
#define CLI_CONFIG_H

#include <stddef.h>

#include "c4gh_cell.h"

typedef struct cli_config {
    char host[C4GH_CELL_DEVICES][256];
    unsigned port[C4GH_CELL_DEVICES];
    int connect_ms;
    int reply_ms;
    int hints; /* REPL hints as you type (1 unless [cli] hints = no) */
} cli_config_t;

/* 127.0.0.1, the spec's ports, 2000 ms timeouts, hints on. */
void cli_config_default(cli_config_t *c);
/* Apply an INI file (at most 1 MiB) over c: sections [robot] [platform] [conditioning]
 * (host, port) and [cli] (connect_timeout_ms, reply_timeout_ms, hints); anything else is an
 * error. 0, or -1 with "PATH:LINE:COL: ..." in err. */
int cli_config_load(cli_config_t *c, const char *path, char *err, size_t errlen);
struct c4gh_tf_file;
/* The same over a file already in memory (lib/host/c4gh_textfile.h). */
int cli_config_parse(cli_config_t *c, struct c4gh_tf_file *f, char *err, size_t errlen);

#endif /* CLI_CONFIG_H */
