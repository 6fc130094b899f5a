/* SPDX-License-Identifier: MIT */
/* libFuzzer target: cell protocol decoders, decimal text parser and line splitter.
   Invariants: no access outside the input, and every accepted line re-encodes to a
   line of the same length that decodes to the same value. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "c4gopen.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_line(const char *line, size_t len)
{
    c4g_cell_instr_t in, in2;
    c4g_cell_reply_t r, r2;
    c4g_cell_diag_t d;
    char out[C4G_CELL_LINE_MAX];
    size_t n = 0;
    if (c4g_cell_instr_decode(line, len, &in, &d) == C4G_OK) {
        if (c4g_cell_instr_encode(&in, out, sizeof out, &n) != C4G_OK || n != len) {
            abort();
        }
        if (c4g_cell_instr_decode(out, n, &in2, NULL) != C4G_OK ||
            memcmp(&in, &in2, sizeof in) != 0) {
            abort();
        }
    } else if (d.column == 0 || d.column > len + 1) {
        abort(); /* the column must point into the line or just past it */
    }
    if (c4g_cell_reply_decode(line, len, &r, &d) == C4G_OK) {
        if (c4g_cell_reply_encode(&r, out, sizeof out, &n) != C4G_OK || n != len) {
            abort();
        }
        if (c4g_cell_reply_decode(out, n, &r2, NULL) != C4G_OK ||
            memcmp(&r, &r2, sizeof r) != 0) {
            abort();
        }
    } else if (d.column == 0 || d.column > len + 1) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* exact-size copy: ASan reports any read past the input */
    char *buf = malloc(size ? size : 1);
    if (buf == NULL) {
        return 0;
    }
    memcpy(buf, data, size);
    check_line(buf, size);

    int32_t v = 0;
    for (int u = 0; u < 3; u++) {
        if (c4g_cell_from_text(buf, size, (c4g_cell_unit_t)u, &v) == C4G_OK) {
            int32_t lim = (u == 2) ? C4G_CELL_INT_MAX : C4G_CELL_COUNTS_MAX;
            if (v > lim || v < -lim) {
                abort();
            }
        }
        if (size >= 8) {
            (void)c4g_cell_field_decode(buf, 8, (c4g_cell_unit_t)u, &v, NULL);
        }
    }

    /* the splitter: chunk sizes taken from the first byte, lines through the decoders */
    char line_buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
    size_t chunk = size ? (size_t)(data[0] % 17U) + 1U : 1U;
    size_t off = 0;
    (void)c4g_cell_split_init(&sp, line_buf, sizeof line_buf);
    while (off < size) {
        size_t k = (size - off < chunk) ? size - off : chunk;
        size_t used = 0;
        if (c4g_cell_split_push(&sp, buf + off, k, &used) != C4G_OK) {
            abort();
        }
        off += used;
        for (;;) {
            c4g_cell_split_event_t ev;
            const char *line = NULL;
            size_t len = 0;
            if (c4g_cell_split_next(&sp, &ev, &line, &len) != C4G_OK) {
                abort();
            }
            if (ev == C4G_CELL_SPLIT_NONE) {
                break;
            }
            if (ev == C4G_CELL_SPLIT_LINE) {
                if (len == 0 || len > sizeof line_buf || line[len - 1] != '\n' ||
                    line < line_buf || line + len > line_buf + sizeof line_buf) {
                    abort();
                }
                check_line(line, len);
            }
        }
    }
    free(buf);
    return 0;
}
