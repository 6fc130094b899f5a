/* SPDX-License-Identifier: MIT */
/* cell-cli command language: human-friendly commands -> cell protocol lines. The device
 * commands, their words, arguments and help come from the library's command table
 * (C4G_CELL_COMMANDS in c4gopen_cell.h); this module adds raw, wait, sleep, help, quit. */
#ifndef CLI_CMD_H
#define CLI_CMD_H

#include <stddef.h>
#include "c4gopen.h"

typedef enum cmd_kind {
    CMD_EMPTY = 0,   /* blank line or comment */
    CMD_SEND,        /* an instruction for a device (encoded in line) */
    CMD_RAW,         /* raw text for a device (CR LF appended) */
    CMD_WAIT,        /* wait <dev> stopped [timeout] */
    CMD_SLEEP,       /* sleep <seconds> */
    CMD_HELP,        /* help [topic] */
    CMD_CLEAR,       /* clear the screen */
    CMD_CONNECT,     /* connect HOST [PORT] | connect DEV HOST[:PORT] */
    CMD_QUIT
} cmd_kind_t;

/* The most times "N CMD" runs a command (as redis-cli's "3 ping"). */
#define CLI_REPEAT_MAX 100000L

typedef struct cli_cmd {
    cmd_kind_t kind;
    int dev;                 /* CELL_DEV_* for SEND/RAW/WAIT */
    c4g_cell_instr_t instr;  /* SEND */
    char line[256];          /* SEND: encoded line; RAW: text + CR LF */
    size_t len;
    double seconds;          /* SLEEP, WAIT timeout */
    char topic[32];          /* HELP */
    char host[256];          /* CONNECT */
    unsigned port;           /* CONNECT: 0 keeps the device's port (ports of all from here) */
    long repeat;             /* "N CMD": run N times (1 without a count) */
} cli_cmd_t;

/* Parse one command; on error returns -1 with a message in err. */
int cli_cmd_parse(const char *text, cli_cmd_t *out, char *err, size_t err_cap);

/* Help: the overview (topic NULL/empty), every command a word names ("servo": srvon and
 * srvof) or a device's commands ("robot"); 0 if found. The overview names the devices'
 * addresses: addr[dev] ("127.0.0.1:2001"), or the default ports when addr is NULL. */
int cli_cmd_help(const char *topic, char *out, size_t cap);
int cli_cmd_help_at(const char *topic, const char *const addr[], char *out, size_t cap);

/* Words completion can offer at word index @p word given the first word. */
const char *const *cli_cmd_words(int word, const char *first, const char *second);

/* The hint shown after the line being typed, as redis-cli shows one: the arguments of the
 * command still to come ("robot mov abs x=1 " -> "y=MM z=MM c=RAD"), with a leading space
 * while the last word is still being typed. Its length; 0 (out "") when there is nothing
 * to show: an unknown or unfinished command word, a word that fits nowhere, every argument
 * given. */
size_t cli_cmd_hint(const char *line, char *out, size_t cap);

#endif /* CLI_CMD_H */
