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
    CMD_QUIT
} cmd_kind_t;

typedef struct cli_cmd {
    cmd_kind_t kind;
    int dev;                 /* CELL_DEV_* for SEND/RAW/WAIT */
    c4g_cell_instr_t instr;  /* SEND */
    char line[256];          /* SEND: encoded line; RAW: text + CR LF */
    size_t len;
    double seconds;          /* SLEEP, WAIT timeout */
    char topic[32];          /* HELP */
} cli_cmd_t;

/* Parse one command; on error returns -1 with a message in err. */
int cli_cmd_parse(const char *text, cli_cmd_t *out, char *err, size_t err_cap);

/* Help: the overview (topic NULL/empty) or one command's help; 0 if found. */
int cli_cmd_help(const char *topic, char *out, size_t cap);

/* Words completion can offer at word index @p word given the first word. */
const char *const *cli_cmd_words(int word, const char *first, const char *second);

/* The hint shown after the line being typed, as redis-cli shows one: the arguments of the
 * command still to come ("robot mov abs x=1 " -> "y=MM z=MM c=RAD"), with a leading space
 * while the last word is still being typed. Its length; 0 (out "") when there is nothing
 * to show: an unknown or unfinished command word, a word that fits nowhere, every argument
 * given. */
size_t cli_cmd_hint(const char *line, char *out, size_t cap);

#endif /* CLI_CMD_H */
