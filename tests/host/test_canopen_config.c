/* SPDX-License-Identifier: MIT */
/* CANopen network configuration INI: the platform's file, every key, and bad files with
   their PATH:LINE:COL, key and reason. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "c4gopen.h"
#include "c4gh_textfile.h"
#include "c4gh_coconfig.h"

static c4gh_co_config_t cfg;

static int parse(const char *text, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    c4gh_tf_open_mem(&f, "coc0.ini", text, strlen(text));
    return c4gh_co_config_parse(&cfg, &f, err, errlen);
}

static void test_platform_file(void **state)
{
    (void)state;
    char err[512] = "";
    assert_int_equal(c4gh_co_config_load(&cfg, FIXTURES_DIR "/canopen/platform.ini", err, sizeof err), 0);
    const c4g_co_net_cfg_t *n = &cfg.net;
    assert_int_equal(n->channel, 0);
    assert_int_equal(n->bitrate, 500000);
    assert_int_equal(n->sync_period_ns, 10000000); /* sync_period_us = 10000 */
    assert_int_equal(n->sdo_timeout_ns, 50000000); /* sdo_timeout_ms = 50 */
    assert_int_equal(n->sdo_retries, 2);
    assert_int_equal(n->n_nodes, 2);
    assert_int_equal(n->node[0].node_id, 1);
    assert_int_equal(n->node[0].device_type, 0x00020192);
    assert_int_equal(n->node[0].watchdog, C4G_CO_WD_HEARTBEAT);
    assert_int_equal(n->node[0].consumer_ms, 300);
    assert_int_equal(n->node[0].flags, C4G_CO_F_RECOVERY);
    assert_int_equal(n->node[0].rx[0].n, 2);
    assert_int_equal(n->node[0].rx[0].entry[0], 0x60410010);
    assert_int_equal(n->node[0].rx[0].entry[1], 0x60640020);
    assert_int_equal(n->node[0].tx[0].n, 3);
    assert_int_equal(n->node[0].tx[0].entry[1], 0x60600008);
    assert_int_equal(n->node[0].tx[0].entry[2], 0x607A0020);
    assert_int_equal(n->node[0].tx[0].trans, 1);
    assert_string_equal(cfg.rx_name[0][0][1], "real_position");
    assert_int_equal(n->node[1].device_type, 0x40020192);
    assert_int_equal(n->node[1].watchdog, C4G_CO_WD_LIFEGUARD);
    assert_int_equal(n->node[1].guard_ms, 100);
    assert_int_equal(n->node[1].life_factor, 3);
    assert_int_equal(n->node[1].station, 2);
    assert_int_equal(n->node[1].axis, 2);
}

static void test_every_key(void **state)
{
    (void)state;
    char err[512] = "";
    const char *text =
        "[channel]\nchannel = 3\nbitrate = 125000\nsync_period_us = 2000\n"
        "[node 127]\nstation = 64\naxis = 32\ndevice_type = 131474\nignore_device_type = yes\n"
        "recovery = 1\nbypass = cycle, watchdog, pdo\nwatchdog = none\n"
        "rxpdo2 = input_word, drive_ideal_position\nrxpdo2_type = 240\n"
        "txpdo4 = ideal_speed\ntxpdo4_type = 255\ntxpdo3 = 0x2000:01/16, torque_reference\n"
        "txpdo2 = output_word, speed_reference\n";
    assert_int_equal(parse(text, err, sizeof err), 0);
    const c4g_co_node_cfg_t *n = &cfg.net.node[0];
    assert_int_equal(cfg.net.channel, 3);
    assert_int_equal(n->node_id, 127);
    assert_int_equal(n->device_type, 131474);
    assert_int_equal(n->flags, 0x1F);
    assert_int_equal(n->watchdog, C4G_CO_WD_NONE);
    assert_int_equal(n->rx[1].trans, 240);
    assert_int_equal(n->rx[1].entry[0], 0x60FD0020);
    assert_int_equal(n->tx[3].trans, 255);
    assert_int_equal(n->tx[2].entry[0], 0x20000110);
    assert_int_equal(n->tx[2].entry[1], 0x60710010);
    assert_int_equal(parse("[node 1]\nbypass = none\nignore_device_type = false\n", err, sizeof err), 0);
    assert_int_equal(cfg.net.node[0].flags, 0);
}

static void test_bad_files(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *want;
    } rows[] = {
        {"[channel]\nbitrate = 9\n[node 1]\n", "coc0.ini:2:11: [channel] bitrate: "},
        {"[channel]\nspeed = 9\n", "coc0.ini:2:1: [channel]: unknown key 'speed'"},
        {"[chan]\nbitrate = 500000\n", "coc0.ini:1:"},
        {"[node 0]\naxis = 1\n", "unknown section [node 0]"},
        {"[node 1]\naxis = 33\n", "coc0.ini:2:8: [node 1] axis: "},
        {"[node 1]\nwatchdog = often\n", "[node 1] watchdog: want heartbeat, lifeguard or none"},
        {"[node 1]\nrecovery = maybe\n", "[node 1] recovery: want true or false"},
        {"[node 1]\nbypass = cycle, boot\n", "[node 1] bypass: want a list of cycle, watchdog, pdo"},
        {"[node 1]\nrxpdo1 = controlword\n", "[node 1] rxpdo1: 'controlword' is not a RxPDO variable"},
        {"[node 1]\ntxpdo1 = ideal_position, ideal_speed, controlword\n", "exceed the 8 bytes"},
        {"[node 1]\ntxpdo1 = , ,\n", "[node 1] txpdo1: no variables"},
        {"[node 1]\ntxpdo1_type = 250\n", "transmission type must be"},
        {"[node 1]\ntxpdo5 = controlword\n", "unknown key 'txpdo5'"},
        {"[node 1]\ndevice_type = 0x1FFFFFFFF\n", "[node 1] device_type: "},
        {"[node 1]\naxis = 1\n[node 2]\nstation = 1\n", "coc0.ini:4: [node 2]: station id already used"},
        {"[node 1]\nheartbeat_ms = 300\n", "coc0.ini:2: [node 1]: consumer_ms must be greater"},
        {"[node 1]\naxis = 1\n[node 2]\naxis = 2\n[node 1]\naxis=3\n", "coc0.ini:5:1: [node 1]: node 1 is configured twice"},
        {"[channel]\nbitrate = 500000\n", "no [node N] section"},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        char err[512] = "";
        if (parse(rows[i].text, err, sizeof err) != -1) {
            fail_msg("row %zu accepted", i);
        }
        if (strstr(err, rows[i].want) == NULL) {
            fail_msg("row %zu: '%s' does not contain '%s'", i, err, rows[i].want);
        }
    }
    /* 17 nodes: the Robox master drives at most 16 per channel */
    char big[2048] = "";
    for (int i = 1; i <= 17; i++) {
        char s[64];
        snprintf(s, sizeof s, "[node %d]\naxis = 1\n", i);
        strcat(big, s);
    }
    char err[512] = "";
    assert_int_equal(parse(big, err, sizeof err), -1);
    assert_non_null(strstr(err, "more than 16 nodes"));
    assert_int_equal(c4gh_co_config_load(&cfg, "/nonexistent/coc0.ini", err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/coc0.ini"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_platform_file),
        cmocka_unit_test(test_every_key),
        cmocka_unit_test(test_bad_files),
    };
    return cmocka_run_group_tests_name("canopen network configuration", tests, NULL, NULL);
}
