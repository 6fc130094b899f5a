/* SPDX-License-Identifier: MIT */
/* Cell protocol line splitter: partial reads, several lines per read, overlong
   lines, buffer limits, misuse. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "c4gopen.h"

/* Feed the whole input in chunks of @p chunk bytes; collect events as text. */
static void run(const char *in, size_t n, size_t chunk, size_t cap, char *out, size_t out_cap)
{
    char *buf = malloc(cap + 2);
    buf[cap] = 0x5A; /* guard */
    buf[cap + 1] = 0x5A;
    c4g_cell_splitter_t sp;
    assert_int_equal(c4g_cell_split_init(&sp, buf, cap), C4G_OK);
    size_t o = 0;
    size_t off = 0;
    out[0] = '\0';
    while (off < n) {
        size_t k = (n - off < chunk) ? (n - off) : chunk;
        size_t done = 0;
        while (done < k) {
            size_t used = 0;
            assert_int_equal(c4g_cell_split_push(&sp, in + off + done, k - done, &used), C4G_OK);
            done += used;
            for (;;) {
                c4g_cell_split_event_t ev;
                const char *line = NULL;
                size_t len = 0;
                assert_int_equal(c4g_cell_split_next(&sp, &ev, &line, &len), C4G_OK);
                if (ev == C4G_CELL_SPLIT_NONE) {
                    break;
                }
                if (ev == C4G_CELL_SPLIT_LINE) {
                    assert_true(len >= 1 && len <= cap);
                    assert_int_equal(line[len - 1], '\n');
                    assert_true(o + len + 2 < out_cap);
                    out[o++] = '[';
                    memcpy(out + o, line, len);
                    o += len;
                    out[o++] = ']';
                } else {
                    assert_true(o + 2 < out_cap);
                    out[o++] = '!';
                }
                out[o] = '\0';
            }
        }
        off += k;
    }
    assert_int_equal((unsigned char)buf[cap], 0x5A);
    assert_int_equal((unsigned char)buf[cap + 1], 0x5A);
    free(buf);
}

static void test_lines_any_chunking(void **state)
{
    (void)state;
    const char *in = "STA\r\nOVR+00050\r\nMOVA+010.000-002.000+005.999-01.2322\r\nSTP\r\n";
    const char *want = "[STA\r\n][OVR+00050\r\n][MOVA+010.000-002.000+005.999-01.2322\r\n][STP\r\n]";
    char out[512];
    for (size_t chunk = 1; chunk <= strlen(in); chunk++) {
        run(in, strlen(in), chunk, C4G_CELL_LINE_MAX, out, sizeof out);
        assert_string_equal(out, want);
    }
    /* partial last line stays buffered, nothing reported */
    run("STA\r\nST", 7, 3, C4G_CELL_LINE_MAX, out, sizeof out);
    assert_string_equal(out, "[STA\r\n]");
    /* bare LF terminates a line too (the decoder then rejects it) */
    run("a\nb\n", 4, 4, 8, out, sizeof out);
    assert_string_equal(out, "[a\n][b\n]");
}

static void test_overlong(void **state)
{
    (void)state;
    char out[512];
    /* a line of exactly cap bytes (LF included) is accepted */
    run("0123456\n", 8, 8, 8, out, sizeof out);
    assert_string_equal(out, "[0123456\n]");
    /* one more byte: dropped, reported once, the next line survives */
    for (size_t chunk = 1; chunk <= 20; chunk++) {
        run("01234567\nSTA\r\n", 14, chunk, 8, out, sizeof out);
        assert_string_equal(out, "!" "[STA\r\n]");
    }
    /* a very long line with no LF: one report, nothing else */
    static char big[65536];
    memset(big, 'X', sizeof big);
    run(big, sizeof big, 1000, C4G_CELL_LINE_MAX, out, sizeof out);
    assert_string_equal(out, "!");
    /* two overlong lines: two reports; lines around them intact */
    const char *in = "OK\r\nAAAAAAAAAAAAAAAAAAAAAAAAA\nBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBB\nER+00001\r\n";
    for (size_t chunk = 1; chunk <= strlen(in); chunk++) {
        run(in, strlen(in), chunk, 16, out, sizeof out);
        assert_string_equal(out, "[OK\r\n]!![ER+00001\r\n]");
    }
}

static void test_misuse(void **state)
{
    (void)state;
    char buf[8];
    c4g_cell_splitter_t sp;
    size_t used = 99;
    c4g_cell_split_event_t ev;
    const char *line;
    size_t len;
    assert_int_equal(c4g_cell_split_init(NULL, buf, 8), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_init(&sp, NULL, 8), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_init(&sp, buf, 3), C4G_ERR_ARG);
    assert_int_equal(c4g_cell_split_init(&sp, buf, 4), C4G_OK);
    assert_int_equal(c4g_cell_split_push(NULL, "a", 1, &used), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_push(&sp, NULL, 1, &used), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_push(&sp, "a", 1, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_push(&sp, NULL, 0, &used), C4G_OK);
    assert_int_equal(used, 0);
    /* a full buffer takes nothing more */
    assert_int_equal(c4g_cell_split_push(&sp, "OK\r\nMORE", 8, &used), C4G_OK);
    assert_int_equal(used, 4);
    assert_int_equal(c4g_cell_split_push(&sp, "X", 1, &used), C4G_OK);
    assert_int_equal(used, 0);
    assert_int_equal(c4g_cell_split_next(&sp, &ev, &line, &len), C4G_OK);
    assert_int_equal(ev, C4G_CELL_SPLIT_LINE);
    assert_int_equal(len, 4);
    assert_memory_equal(line, "OK\r\n", 4);
    assert_int_equal(c4g_cell_split_next(&sp, &ev, &line, &len), C4G_OK);
    assert_int_equal(ev, C4G_CELL_SPLIT_NONE);
    assert_int_equal(c4g_cell_split_next(NULL, &ev, &line, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_next(&sp, NULL, &line, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_next(&sp, &ev, NULL, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_next(&sp, &ev, &line, NULL), C4G_ERR_NULL);
    c4g_cell_splitter_t zero;
    memset(&zero, 0, sizeof zero);
    assert_int_equal(c4g_cell_split_push(&zero, "a", 1, &used), C4G_ERR_NULL);
    assert_int_equal(c4g_cell_split_next(&zero, &ev, &line, &len), C4G_ERR_NULL);
}

/* The splitter feeding the decoder: a realistic server loop. */
static void test_with_decoder(void **state)
{
    (void)state;
    char buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
    assert_int_equal(c4g_cell_split_init(&sp, buf, sizeof buf), C4G_OK);
    const char *stream = "SRVON\r\nOVR+00080\r\nGARBAGE\r\nMOVR+01.0000-01.0000\r\n";
    size_t used;
    assert_int_equal(c4g_cell_split_push(&sp, stream, strlen(stream), &used), C4G_OK);
    assert_int_equal(used, strlen(stream));
    c4g_cell_cmd_t want[] = {C4G_CELL_CMD_SRVON, C4G_CELL_CMD_OVR, C4G_CELL_CMD_COUNT_,
                             C4G_CELL_CMD_MOV};
    for (size_t i = 0; i < 4; i++) {
        c4g_cell_split_event_t ev;
        const char *line;
        size_t len;
        c4g_cell_instr_t in;
        c4g_cell_diag_t d;
        assert_int_equal(c4g_cell_split_next(&sp, &ev, &line, &len), C4G_OK);
        assert_int_equal(ev, C4G_CELL_SPLIT_LINE);
        c4g_status_t st = c4g_cell_instr_decode(line, len, &in, &d);
        if (want[i] == C4G_CELL_CMD_COUNT_) {
            assert_int_equal(st, C4G_ERR_CELL_HEAD);
            assert_int_equal(d.column, 1);
        } else {
            assert_int_equal(st, C4G_OK);
            assert_int_equal(in.cmd, want[i]);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lines_any_chunking),
        cmocka_unit_test(test_overlong),
        cmocka_unit_test(test_misuse),
        cmocka_unit_test(test_with_decoder),
    };
    return cmocka_run_group_tests_name("cell line splitter", tests, NULL, NULL);
}
