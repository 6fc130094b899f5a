/* SPDX-License-Identifier: MIT */
/* libFuzzer: cell-cli's command language (tools/cell-cli/cli_cmd.c) on one typed line: the
 * parser, the hint shown as the line is typed, and the completion words. Invariants: the
 * parser accepts (a device line encoded with CR LF, a repeat count 1..CLI_REPEAT_MAX) or
 * fails with a message; help on any topic ends inside its buffer; a hint fits
 * its buffer, its length is returned, and it holds only printable ASCII (it is drawn on the
 * terminal as it is, before the line is even complete). */
#include <ctype.h>

#include "fuzz_text.h"
#include "cli_cmd.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_hint(const char *line)
{
    char hint[64];
    size_t n;
    memset(hint, 0x55, sizeof hint);
    n = cli_cmd_hint(line, hint, sizeof hint);
    if (n >= sizeof hint || memchr(hint, '\0', sizeof hint) == NULL || strlen(hint) != n) {
        abort();
    }
    for (size_t i = 0; i < n; i++) {
        if (!isprint((unsigned char)hint[i])) {
            abort();
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char line[1024];
    char err[256];
    cli_cmd_t cmd;
    const char *const *w;
    char *buf = fuzz_copy(data, size);
    size_t n = size < sizeof line - 1U ? size : sizeof line - 1U;
    if (buf == NULL) {
        return 0;
    }
    memcpy(line, buf, n);
    line[n] = '\0';
    memset(err, 0x55, sizeof err);
    if (cli_cmd_parse(line, &cmd, err, sizeof err) != 0) {
        if (memchr(err, '\0', sizeof err) == NULL || err[0] == '\0') {
            abort();
        }
    } else if ((cmd.kind == CMD_SEND &&
                (cmd.len < 2U || cmd.len > sizeof cmd.line || cmd.line[cmd.len - 2U] != '\r' ||
                 cmd.line[cmd.len - 1U] != '\n')) ||
               cmd.repeat < 1 || cmd.repeat > CLI_REPEAT_MAX ||
               (cmd.kind == CMD_CONNECT && memchr(cmd.host, '\0', sizeof cmd.host) == NULL)) {
        abort();
    }
    /* the line as a help topic, into a small buffer: terminated, never overrun */
    {
        char help[200];
        static const char *const addr[3] = {"h:1", "h:2", "h:3"};
        memset(help, 0x55, sizeof help);
        (void)cli_cmd_help_at(line, (n & 1U) != 0U ? addr : NULL, help, sizeof help);
        if (memchr(help, '\0', sizeof help) == NULL) {
            abort();
        }
    }
    /* every prefix of the line, as the hint is computed at each key */
    for (size_t k = 0; k <= n && k < 96U; k++) {
        char c = line[k];
        line[k] = '\0';
        check_hint(line);
        line[k] = c;
    }
    check_hint(line);
    w = cli_cmd_words((int)(n % 5U), line, n > 3U ? line + 3 : NULL);
    for (size_t i = 0; w != NULL && w[i] != NULL; i++) {
        if (w[i][0] == '\0') {
            abort();
        }
    }
    free(buf);
    return 0;
}
