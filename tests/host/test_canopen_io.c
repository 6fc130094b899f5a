/* SPDX-License-Identifier: MIT */
/* CANopen bus I/O of the tools: candump log lines, the pcap (DLT_CAN_SOCKETCAN) read back
   through libpcap, SocketCAN errors, and a real vcan round trip where the kernel has one. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "c4gopen.h"
#include "c4gh_can.h"

#include <pcap/pcap.h>

static c4g_co_frame_t fr(uint16_t id, uint8_t dlc, const char *bytes, int rtr)
{
    c4g_co_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    f.rtr = (uint8_t)rtr;
    if (bytes != NULL) {
        memcpy(f.data, bytes, dlc);
    }
    return f;
}

static void test_candump_lines(void **state)
{
    (void)state;
    char line[96];
    c4g_co_frame_t f = fr(0x601, 8, "\x40\x00\x10\x00\x00\x00\x00\x00", 0);
    c4gh_co_candump_line(line, sizeof line, "vcan0", 1700000000123456ULL, &f);
    assert_string_equal(line, "(1700000000.123456) vcan0 601#4000100000000000");
    f = fr(0x080, 0, NULL, 0);
    c4gh_co_candump_line(line, sizeof line, "can1", 5, &f);
    assert_string_equal(line, "(0.000005) can1 080#");
    f = fr(0x702, 1, NULL, 1);
    c4gh_co_candump_line(line, sizeof line, "vcan0", 0, &f);
    assert_string_equal(line, "(0.000000) vcan0 702#R");
}

static void test_logs_read_back(void **state)
{
    (void)state;
    char dir[] = "/tmp/c4g-co-io-XXXXXX";
    char cd[64], pc[64], err[256] = "";
    assert_non_null(mkdtemp(dir));
    snprintf(cd, sizeof cd, "%s/bus.log", dir);
    snprintf(pc, sizeof pc, "%s/bus.pcap", dir);
    c4gh_co_buslog_t l;
    assert_int_equal(c4gh_co_buslog_open(&l, cd, pc, "vcan0", 1000000, err, sizeof err), 0);
    c4g_co_frame_t a = fr(0x000, 2, "\x80\x00", 0);
    c4g_co_frame_t b = fr(0x702, 1, NULL, 1);
    b.t_ns = 2500000; /* the logs show it in us: 2500 */
    c4gh_co_buslog_cb(&l, &a);
    c4gh_co_buslog_write(&l, &b);
    assert_int_equal(l.frames, 2);
    c4gh_co_buslog_close(&l);
    /* candump */
    FILE *fp = fopen(cd, "r");
    char line[128];
    assert_non_null(fp);
    assert_non_null(fgets(line, sizeof line, fp));
    assert_string_equal(line, "(1.000000) vcan0 000#8000\n");
    assert_non_null(fgets(line, sizeof line, fp));
    assert_string_equal(line, "(1.002500) vcan0 702#R\n");
    fclose(fp);
    /* pcap through libpcap: link type, struct can_frame layout, times */
    char perr[PCAP_ERRBUF_SIZE];
    pcap_t *p = pcap_open_offline(pc, perr);
    assert_non_null(p);
    assert_int_equal(pcap_datalink(p), 227);
    struct pcap_pkthdr *h;
    const u_char *d;
    assert_int_equal(pcap_next_ex(p, &h, &d), 1);
    assert_int_equal(h->caplen, 16);
    const uint8_t want_a[16] = {0, 0, 0, 0, 2, 0, 0, 0, 0x80, 0, 0, 0, 0, 0, 0, 0};
    assert_memory_equal(d, want_a, 16);
    assert_int_equal(h->ts.tv_sec, 1);
    assert_int_equal(pcap_next_ex(p, &h, &d), 1);
    const uint8_t want_b[8] = {0x40, 0, 0x07, 0x02, 1, 0, 0, 0}; /* RTR flag, id 0x702 */
    assert_memory_equal(d, want_b, 8);
    assert_int_equal(h->ts.tv_usec, 2500);
    assert_int_equal(pcap_next_ex(p, &h, &d), -2);
    pcap_close(p);
    /* unwritable paths are reported with the path */
    assert_int_equal(c4gh_co_buslog_open(&l, "/nonexistent/x.log", NULL, NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.log: cannot create the candump log"));
    assert_int_equal(c4gh_co_buslog_open(&l, NULL, "/nonexistent/x.pcap", NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.pcap: cannot create the pcap"));
    unlink(cd);
    unlink(pc);
    rmdir(dir);
}

static void test_socketcan(void **state)
{
    (void)state;
    char err[256] = "";
    assert_int_equal(c4gh_co_socketcan_open("nosuchcan9", err, sizeof err), -1);
    assert_non_null(strstr(err, "nosuchcan9"));
    assert_int_equal(c4gh_co_socketcan_open("a-very-long-interface-name", err, sizeof err), -1);
    assert_non_null(strstr(err, "interface name too long"));
    /* a real round trip where a vcan interface exists (tests/e2e/test_canopen.py creates one
       when it can); otherwise say why it is skipped */
    int a = c4gh_co_socketcan_open("vcan0", err, sizeof err);
    if (a < 0) {
        print_message("SocketCAN round trip skipped: %s\n", err);
        return;
    }
    int b = c4gh_co_socketcan_open("vcan0", err, sizeof err);
    assert_true(b >= 0);
    c4g_co_frame_t f = fr(0x181, 6, "\x37\x02\x01\x02\x03\x04", 0), g;
    assert_int_equal(c4gh_co_socketcan_send(a, &f), 0);
    int got = 0;
    for (int i = 0; i < 1000 && got == 0; i++) {
        got = c4gh_co_socketcan_recv(b, &g, 7);
        if (got == 0) {
            usleep(1000);
        }
    }
    assert_int_equal(got, 1);
    assert_int_equal(g.id, 0x181);
    assert_int_equal(g.dlc, 6);
    assert_memory_equal(g.data, f.data, 6);
    assert_int_equal(g.t_ns, 7);
    close(a);
    close(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_candump_lines),
        cmocka_unit_test(test_logs_read_back),
        cmocka_unit_test(test_socketcan),
    };
    return cmocka_run_group_tests_name("canopen bus I/O (candump, pcap, SocketCAN)", tests, NULL, NULL);
}
