/* SPDX-License-Identifier: MIT */
/* cell_common: what cell-sim and cell-cli share (device names, default ports,
 * host:port parsing, monotonic time, socket helpers). No main(), no heavy deps. */
#ifndef C4GH_CELL_H
#define C4GH_CELL_H

#include "c4gh_clock.h"

#include <stddef.h>
#include <stdint.h>

#define C4GH_CELL_DEVICES 3
#define C4GH_CELL_DEV_ROBOT 0
#define C4GH_CELL_DEV_PLATFORM 1
#define C4GH_CELL_DEV_CONDITIONING 2

/* "robot", "platform", "conditioning" */
const char *c4gh_cell_dev_name(int dev);
/* Spec ports: 2001, 2002, 2003. */
unsigned c4gh_cell_dev_default_port(int dev);
/* Device from a name or a unique prefix ("r", "plat", "cond"); -1 if none. */
int c4gh_cell_dev_parse(const char *s);


/* "host:port", "host" (port unchanged) or ":port"; 0 on success, -1 on error. */
int c4gh_cell_parse_hostport(const char *s, char *host, size_t host_cap, unsigned *port);
/* Strict unsigned/double parsing of a whole string; 0 on success. */
int c4gh_cell_parse_uint(const char *s, unsigned long max, unsigned long *out);
int c4gh_cell_parse_double(const char *s, double *out);

/* Non-blocking TCP connect to host:port (IPv4 literal or name) with a timeout.
 * Returns a blocking fd, or -1 with *err set to a static description. */
int c4gh_cell_tcp_connect(const char *host, unsigned port, int timeout_ms, const char **err);
/* A non-blocking TCP listener on addr:port (SO_REUSEADDR); -1 with errno set on failure. */
int c4gh_cell_tcp_listen(const char *addr, unsigned port, int backlog);
/* "a.b.c.d:port" of a socket's peer (or "?"). */
void c4gh_cell_peer_string(int fd, char *buf, size_t cap);

#endif /* C4GH_CELL_H */
