/* SPDX-License-Identifier: MIT */
/* CANopen network configuration: one INI file per channel, in the spirit of the Robox
 * COCn.CFG files (docs/canopen.md, "Network configuration"). Parsed with inih through
 * c4g_textfile; every error names PATH:LINE:COL, the key and the reason. */
#ifndef C4GH_COCONFIG_H
#define C4GH_COCONFIG_H

#include <stddef.h>
#include "c4gopen_canopen.h"
#include "c4gh_textfile.h"

typedef struct c4gh_co_config {
    c4g_co_net_cfg_t net;
    unsigned node_line[C4G_CO_MAX_NODES]; /* line of each [node N] section */
    /* names of the mapped variables, for the diagnostic commands */
    char rx_name[C4G_CO_MAX_NODES][C4G_CO_MAX_PDO][C4G_CO_MAX_ENTRIES][24];
    char tx_name[C4G_CO_MAX_NODES][C4G_CO_MAX_PDO][C4G_CO_MAX_ENTRIES][24];
    int cur;                              /* parser: slot of the current section, -1 none */
} c4gh_co_config_t;

/* Parses a configuration from memory or a file; after the syntax, the whole network is
 * checked (c4g_co_net_check) and an error names the node's section line. 0 or -1. */
int c4gh_co_config_parse(c4gh_co_config_t *c, c4gh_tf_file_t *f, char *err, size_t errlen);
int c4gh_co_config_load(c4gh_co_config_t *c, const char *path, char *err, size_t errlen);
/* The mapping entry of a variable kind of the Robox documentation's lists (or "0xIIII:SS/BITS"). */
int c4gh_co_config_kind(const char *name, int rx, uint32_t *entry);

#endif /* C4GH_COCONFIG_H */
