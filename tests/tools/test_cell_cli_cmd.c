/* SPDX-License-Identifier: MIT */
/* cell-cli's command language is derived from the library's command table: every row's
 * words parse, encode to the row's head and have help; the usage messages keep their
 * wording (the tool sources are included directly). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "c4gh_cell.h"
/* intrusive: the alternatives table and its lookup are static to cli_cmd.c */
#include "../../tools/cell-cli/cli_cmd.c"

/* The smallest valid arguments of a layout for a device. */
static const char *args_of(c4g_cell_args_t a, int dev)
{
    switch (a) {
    case C4G_CELL_ARGS_INT:
        return " 1";
    case C4G_CELL_ARGS_INT_ACTION:
        return " 1 open";
    case C4G_CELL_ARGS_MODE_POSE:
        return dev == C4GH_CELL_DEV_ROBOT ? " abs x=1 y=2 z=3 c=0.5" : " rel a=0.1";
    case C4G_CELL_ARGS_CLEAR_POSE:
        return " clear=60 x=1 y=2 z=3 c=0.5";
    case C4G_CELL_ARGS_NONE:
    default:
        return "";
    }
}

static void test_every_row_parses(void **st)
{
    (void)st;
    for (size_t i = 0; i < N_ROWS; i++) {
        alt_t a;
        c4g_cell_cmd_info_t info;
        assert_int_equal(c4g_cell_cmd_info(k_rows[i].cmd, &info), C4G_OK);
        for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
            if ((k_rows[i].devices & (1U << d)) == 0U) {
                continue;
            }
            for (int k = 0; alt_get(k_rows[i].words, k, &a); k++) {
                char text[128], err[256], help[512];
                cli_cmd_t cmd;
                snprintf(text, sizeof text, "%s %s%s%s%s", c4gh_cell_dev_name(d), a.first,
                         a.second[0] != '\0' ? " " : "", a.second, args_of(k_rows[i].args, d));
                if (cli_cmd_parse(text, &cmd, err, sizeof err) != 0) {
                    fail_msg("'%s': %s", text, err);
                }
                assert_int_equal(cmd.kind, CMD_SEND);
                assert_int_equal(cmd.dev, d);
                assert_int_equal(cmd.instr.cmd, k_rows[i].cmd);
                assert_memory_equal(cmd.line, info.head, info.head_len);
                assert_int_equal(cli_cmd_help(a.first, help, sizeof help), 0);
            }
        }
    }
}

static void expect_err(const char *text, const char *msg)
{
    cli_cmd_t cmd;
    char err[256];
    assert_int_equal(cli_cmd_parse(text, &cmd, err, sizeof err), -1);
    assert_string_equal(err, msg);
}

static void test_messages(void **st)
{
    cli_cmd_t cmd;
    char err[256];
    (void)st;
    expect_err("robot", "missing command after 'robot' (try: help)");
    expect_err("robot servo", "usage: robot servo on|off");
    expect_err("robot servo on now", "usage: robot servo on|off");
    expect_err("robot sta now", "'sta' takes no arguments");
    expect_err("robot ovr", "missing override (percent)");
    expect_err("robot override 1 2", "usage: robot ovr PERCENT");
    expect_err("robot ovr 101", "override (percent) must be an integer 0..100, got '101'");
    expect_err("conditioning acq 1.5", "camera id must be an integer 0..99999, got '1.5'");
    expect_err("conditioning hnd 1", "usage: conditioning hnd GRIPPER open|close");
    expect_err("conditioning mov abs", "the conditioning controller has no axes");
    expect_err("robot mov", "usage: robot mov abs|rel x=MM y=MM z=MM c=RAD");
    expect_err("platform mov up", "usage: platform mov abs|rel a=RAD b=RAD");
    expect_err("platform pnp", "pnp is a robot command");
    expect_err("robot mov abs x=1", "missing y= (absolute targets need every axis)");
    expect_err("robot mov abs x=1 x=2", "axis 'x' given twice");
    expect_err("robot mov abs clear=1", "unknown axis 'clear' for the robot (use x, y, z, c)");
    expect_err("robot pnp q=1", "unknown axis 'q' for the robot (use clear, x, y, z, c)");
    expect_err("robot pnp x=1 y=1 z=1 c=1", "missing clear= (absolute targets need every axis)");
    expect_err("robot mov rel x", "expected key=value, got 'x'");
    expect_err("robot mov rel x=1000", "x=1000 is out of range (+-999.999 mm)");
    expect_err("robot mov rel c=abc", "c: not a number: 'abc'");
    expect_err("robot fly", "unknown command 'fly' for the robot (try: help)");
    expect_err("fly", "unknown device or command 'fly' (try: help)");
    assert_int_equal(cli_cmd_parse("r servo off", &cmd, err, sizeof err), 0);
    assert_string_equal(cmd.line, "SRVOF\r\n");
    assert_int_equal(cli_cmd_parse("c gripper 0 CLOSE", &cmd, err, sizeof err), 0);
    assert_string_equal(cmd.line, "HND+00000CLOSE\r\n");
    assert_int_equal(cli_cmd_parse("p move rel b=-0.25", &cmd, err, sizeof err), 0);
    assert_string_equal(cmd.line, "MOVR+00.0000-00.2500\r\n");
}

static void test_help_and_words(void **st)
{
    char out[4096];
    const char *const *w;
    (void)st;
    assert_int_equal(cli_cmd_help("", out, sizeof out), 0);
    for (size_t i = 0; i < N_ROWS; i++) {
        char first[128];
        snprintf(first, sizeof first, "\n  %.*s\n", (int)strcspn(k_rows[i].help, "\n"),
                 k_rows[i].help);
        assert_non_null(strstr(out, first)); /* every row indented, its first line whole */
    }
    /* every line between the two-line heading and the closing line is indented */
    {
        const char *p = strchr(strchr(out, '\n') + 1, '\n') + 1;
        const char *last = strstr(out, "help COMMAND shows");
        assert_non_null(last);
        for (; p < last; p = strchr(p, '\n') + 1) {
            assert_true(p[0] == ' ' && p[1] == ' ');
        }
    }
    assert_non_null(strstr(out, "\n  wait DEV stopped"));
    assert_non_null(strstr(out, "\n  clear "));
    assert_non_null(cli_cmd_words(1, "ROBOT", NULL));
    {
        cli_cmd_t c;
        char e[64];
        assert_int_equal(cli_cmd_parse("CLEAR", &c, e, sizeof e), 0);
        assert_int_equal(c.kind, CMD_CLEAR);
        assert_int_equal(cli_cmd_parse("ROBOT STA", &c, e, sizeof e), 0);
        assert_string_equal(c.line, "STA\r\n");
    }
    assert_int_equal(cli_cmd_help("servo", out, sizeof out), 0);
    assert_non_null(strstr(out, "(SRVON)"));
    assert_int_equal(cli_cmd_help("srvoff", out, sizeof out), 0);
    assert_non_null(strstr(out, "(SRVOF)"));
    assert_int_equal(cli_cmd_help("raw", out, sizeof out), 0);
    assert_int_equal(cli_cmd_help("nope", out, sizeof out), -1);
    w = cli_cmd_words(1, "conditioning", NULL);
    assert_string_equal(w[0], "rst");
    assert_string_equal(w[1], "clo");
    assert_string_equal(w[2], "acq");
    assert_string_equal(w[3], "hnd");
    assert_null(w[4]);
    w = cli_cmd_words(2, "robot", "mov");
    assert_string_equal(w[0], "abs");
    w = cli_cmd_words(3, "platform", "mov");
    assert_string_equal(w[0], "a=");
    w = cli_cmd_words(2, "robot", "pnp");
    assert_string_equal(w[0], "clear=");
    w = cli_cmd_words(3, "c", "hnd");
    assert_string_equal(w[1], "close");
    assert_null(cli_cmd_words(2, "robot", "sta"));
    w = cli_cmd_words(1, "help", NULL);
    assert_string_equal(w[0], "sta");
}

static void expect_hint(const char *line, const char *want)
{
    char out[256];
    size_t n = cli_cmd_hint(line, out, sizeof out);
    if (strcmp(out, want) != 0 || n != strlen(want)) {
        fail_msg("hint of '%s': '%s' (%zu), want '%s'", line, out, n, want);
    }
}

/* The hint drops the arguments already typed: in order for choices and placeholders, by
 * key for poses; an unknown or unfinished word, or one that fits nowhere, has none. */
static void test_hints(void **st)
{
    char small[8];
    (void)st;
    expect_hint("", "");
    expect_hint("   ", "");
    expect_hint("rob", "");
    expect_hint("robot", " sta|srvon|srvof|ovr|mov|stp|rst|clo|itr|pnp");
    expect_hint("r ", "sta|srvon|srvof|ovr|mov|stp|rst|clo|itr|pnp");
    expect_hint("conditioning ", "rst|clo|acq|hnd");
    expect_hint("robot st", "");
    expect_hint("robot sta", "");
    expect_hint("robot ovr", " PERCENT");
    expect_hint("ROBOT OVERRIDE ", "PERCENT");
    expect_hint("robot ovr 5", "");
    expect_hint("robot ovr 5 ", "");
    expect_hint("robot servo", " on|off");
    expect_hint("robot servo ", "on|off");
    expect_hint("robot servo o", "");
    expect_hint("robot servo on", "");
    expect_hint("robot servo up ", "");
    expect_hint("robot mov ", "abs|rel x=MM y=MM z=MM c=RAD");
    expect_hint("robot mov abs", " x=MM y=MM z=MM c=RAD");
    expect_hint("robot mov abs ", "x=MM y=MM z=MM c=RAD");
    expect_hint("robot mov abs x=1 ", "y=MM z=MM c=RAD");
    expect_hint("robot mov abs x=1", " y=MM z=MM c=RAD");
    expect_hint("robot mov ABS Z=1 x=2 ", "y=MM c=RAD");
    expect_hint("robot mov abs x", "");
    expect_hint("robot mov abs x=1 x=2 ", "");
    expect_hint("robot mov abs x=1 y=1 z=1 c=1", "");
    expect_hint("robot mov abs q=1 ", "");
    expect_hint("robot mov up ", "");
    expect_hint("robot mov rel y=1 ", "[x=MM] [z=MM] [c=RAD]");
    expect_hint("platform move abs ", "a=RAD b=RAD");
    expect_hint("platform mov rel b=1 ", "[a=RAD]");
    expect_hint("robot pnp x=1 ", "clear=MM y=MM z=MM c=RAD");
    expect_hint("platform pnp ", "");
    expect_hint("platform acq ", "");
    expect_hint("conditioning hnd ", "GRIPPER open|close");
    expect_hint("conditioning hnd 1 ", "open|close");
    expect_hint("conditioning hnd 1 shut ", "");
    expect_hint("wait ", "robot|platform stopped [TIMEOUT]");
    expect_hint("wait r ", "stopped [TIMEOUT]");
    expect_hint("wait conditioning ", "");
    expect_hint("wait platform stopped ", "[TIMEOUT]");
    expect_hint("raw ", "robot|platform|conditioning TEXT");
    expect_hint("raw robot ", "TEXT");
    expect_hint("raw robot OVR+00050", "");
    expect_hint("sleep", " SECONDS");
    expect_hint("help ", "[COMMAND]");
    expect_hint("clear ", "");
    expect_hint("bogus ", "");
    expect_hint("robot mov abs # x= ", "");
    expect_hint("robot a b c d e f g h i j k l m ", "");
    /* a hint longer than the buffer is cut, never overrun */
    assert_int_equal(cli_cmd_hint("robot mov ", small, sizeof small), sizeof small - 1);
    assert_string_equal(small, "abs|rel");
}

/* The REPL habits of redis-cli users: "N CMD", connect, help in use, help by word/device */
static void test_repeat_connect_help(void **st)
{
    char out[4096], e[128];
    cli_cmd_t c;
    const char *const addr[3] = {"10.0.0.5:3000", "10.0.0.5:3001", "10.0.0.6:2003"};
    (void)st;
    assert_int_equal(cli_cmd_parse("robot sta", &c, e, sizeof e), 0);
    assert_int_equal(c.repeat, 1);
    assert_int_equal(cli_cmd_parse("  5 robot sta", &c, e, sizeof e), 0);
    assert_int_equal(c.kind, CMD_SEND);
    assert_int_equal(c.repeat, 5);
    assert_string_equal(c.line, "STA\r\n");
    assert_int_equal(cli_cmd_parse("3 raw platform STA", &c, e, sizeof e), 0);
    assert_int_equal(c.kind, CMD_RAW);
    assert_int_equal(c.repeat, 3);
    assert_int_equal(cli_cmd_parse("0 robot sta", &c, e, sizeof e), -1);
    assert_string_equal(e, "N COMMAND: N must be 1..100000");
    assert_int_equal(cli_cmd_parse("100001 robot sta", &c, e, sizeof e), -1);
    assert_int_equal(cli_cmd_parse("99999999999999999999 robot sta", &c, e, sizeof e), -1);
    assert_string_equal(e, "N COMMAND: N must be 1..100000");
    assert_int_equal(cli_cmd_parse("2 quit", &c, e, sizeof e), -1);
    assert_string_equal(e, "N COMMAND: repeats a device command, wait or sleep");
    assert_int_equal(cli_cmd_parse("2 robot nope", &c, e, sizeof e), -1);
    assert_string_equal(e, "unknown command 'nope' for the robot (try: help)");
    assert_int_equal(cli_cmd_parse("2001x", &c, e, sizeof e), -1);
    assert_string_equal(e, "unknown device or command '2001x' (try: help)");

    assert_int_equal(cli_cmd_parse("connect 10.0.0.5 3000", &c, e, sizeof e), 0);
    assert_int_equal(c.kind, CMD_CONNECT);
    assert_int_equal(c.dev, -1);
    assert_string_equal(c.host, "10.0.0.5");
    assert_int_equal(c.port, 3000);
    assert_int_equal(cli_cmd_parse("connect cellhost", &c, e, sizeof e), 0);
    assert_string_equal(c.host, "cellhost");
    assert_int_equal(c.port, 0);
    assert_int_equal(cli_cmd_parse("connect plat 10.0.0.7:2100", &c, e, sizeof e), 0);
    assert_int_equal(c.dev, C4GH_CELL_DEV_PLATFORM);
    assert_string_equal(c.host, "10.0.0.7");
    assert_int_equal(c.port, 2100);
    assert_int_equal(cli_cmd_parse("connect 10.0.0.5 70000", &c, e, sizeof e), -1);
    assert_string_equal(e, "PORT must be an integer 1..65533, got '70000'");
    assert_int_equal(cli_cmd_parse("connect", &c, e, sizeof e), -1);
    assert_int_equal(cli_cmd_parse("connect a:1", &c, e, sizeof e), -1);

    /* the overview names the addresses in use */
    assert_int_equal(cli_cmd_help_at("", addr, out, sizeof out), 0);
    {
        static const char want[] = "Devices: robot (10.0.0.5:3000), platform (10.0.0.5:3001), "
                                   "conditioning (10.0.0.6:2003);\n";
        assert_memory_equal(out, want, sizeof want - 1);
    }
    assert_null(strstr(out, "2001"));
    /* a word names every row it starts: servo on and servo off */
    assert_int_equal(cli_cmd_help("servo", out, sizeof out), 0);
    assert_non_null(strstr(out, "(SRVON)"));
    assert_non_null(strstr(out, "(SRVOF)"));
    /* a device: its commands only, DEV replaced */
    assert_int_equal(cli_cmd_help("robot", out, sizeof out), 0);
    assert_memory_equal(out, "Commands of the robot:\n  robot sta ", 34);
    assert_non_null(strstr(out, "\n  robot pnp "));
    assert_null(strstr(out, "acq"));
    assert_null(strstr(out, "platform mov"));
    assert_null(strstr(out, "DEV"));
    assert_int_equal(cli_cmd_help("cond", out, sizeof out), 0);
    assert_non_null(strstr(out, "\n  conditioning acq CAMERA"));
    assert_null(strstr(out, " sta "));
    assert_int_equal(cli_cmd_help("N", out, sizeof out), 0);
    assert_non_null(strstr(out, "5 robot sta"));
    assert_string_equal(cli_cmd_words(0, "", NULL)[6], "connect");
    /* the hint of a repeated command is the command's */
    assert_true(cli_cmd_hint("3 robot ovr ", out, sizeof out) > 0);
    assert_string_equal(out, "PERCENT");
    assert_true(cli_cmd_hint("12 robot mov abs x=1 ", out, sizeof out) > 0);
    assert_string_equal(out, "y=MM z=MM c=RAD");
    assert_int_equal(cli_cmd_hint("3", out, sizeof out), 0);
    assert_int_equal(cli_cmd_hint("3 connect ", out, sizeof out), 11);
    assert_string_equal(out, "HOST [PORT]");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_row_parses),
        cmocka_unit_test(test_messages),
        cmocka_unit_test(test_help_and_words),
        cmocka_unit_test(test_hints),
        cmocka_unit_test(test_repeat_connect_help),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
