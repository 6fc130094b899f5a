/* SPDX-License-Identifier: MIT */
/* cell-cli canopen: one Robox CANopen diagnostic command (CO_RNMT, CO_ROBJ, ...) sent to
 * cell-sim's CANopen shell (the platform's port + 10), its reply printed. */
#ifndef CLI_CANOPEN_H
#define CLI_CANOPEN_H

/* 0 reply printed, 1 the shell answered ERR or no connection, 2 usage. */
int cli_canopen_run(const char *host, unsigned port, int n, char **words, int timeout_ms);

#endif /* CLI_CANOPEN_H */
