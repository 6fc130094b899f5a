/* SPDX-License-Identifier: MIT */
/* cell-cli command language: human-friendly commands -> cell protocol lines. */
#ifndef CLI_CMD_H
#define CLI_CMD_H

#include <stddef.h>
#include "c4gopen.h"

typedef enum cli_kind {
    CLI_EMPTY = 0,   /* blank line or comment */
    CLI_SEND,        /* an instruction for a device (encoded in line) */
    CLI_RAW,         /* raw text for a device (CR LF appended) */
    CLI_WAIT,        /* wait <dev> stopped [timeout] */
    CLI_SLEEP,       /* sleep <seconds> */
    CLI_HELP,        /* help [topic] */
    CLI_QUIT
} cli_kind_t;

typedef struct cli_cmd {
    cli_kind_t kind;
    int dev;                 /* CELL_DEV_* for SEND/RAW/WAIT */
    c4g_cell_instr_t instr;  /* SEND */
    char line[256];          /* SEND: encoded line; RAW: text + CR LF */
    size_t len;
    double seconds;          /* SLEEP, WAIT timeout */
    char topic[32];          /* HELP */
} cli_cmd_t;

/* Parse one command; on error returns -1 with a message in err. */
int cli_parse(const char *text, cli_cmd_t *out, char *err, size_t err_cap);

/* Help: the overview (topic NULL/empty) or one command's help; 0 if found. */
int cli_help(const char *topic, char *out, size_t cap);

/* Words completion can offer at word index @p word given the first word. */
const char *const *cli_words(int word, const char *first, const char *second);

#endif /* CLI_CMD_H */
