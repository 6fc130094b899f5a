/* SPDX-License-Identifier: MIT */
/* libFuzzer: cell-cli's INI file (tools/cell-cli/cli_config.c through the shared INI
 * layer and inih). Invariants: an error is one well-formed "PATH:..." message; an
 * accepted file leaves non-empty hosts, ports 1..65535, timeouts 1..600000 ms and hints
 * 0 or 1. */
#include "fuzz_text.h"
#include "cli_config.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cli_config_t c;
    char err[512];
    c4gh_tf_file_t f;
    char *buf = fuzz_copy(data, size);
    int d;
    if (buf == NULL) {
        return 0;
    }
    cli_config_default(&c);
    c4gh_tf_open_mem(&f, "f.ini", buf, size);
    memset(err, 0x55, sizeof err);
    if (cli_config_parse(&c, &f, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.ini");
        free(buf);
        return 0;
    }
    for (d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (c.host[d][0] == '\0' || memchr(c.host[d], '\0', sizeof c.host[d]) == NULL ||
            c.port[d] < 1U || c.port[d] > 65535U) {
            abort();
        }
    }
    if (c.connect_ms < 1 || c.connect_ms > 600000 || c.reply_ms < 1 || c.reply_ms > 600000 ||
        (c.hints != 0 && c.hints != 1)) {
        abort();
    }
    free(buf);
    return 0;
}
