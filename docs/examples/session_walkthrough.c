/* SPDX-License-Identifier: MIT */
/* Library-level session, no sockets: a synthetic controller does the field facts cold
 * start (9 sync packets, the figure 10.1 init packet, 2 sync packets) and 2 s of cyclic
 * packets at 2 ms with a few faults; the PC-side engine answers each. Prints the
 * initialization packet like the manual's figure 10.1, then the session counters and the
 * chapter 22 timing report. Exit status 0 only if every expectation holds. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <string.h>

static void print_arm_ints(const char *title, int32_t v[C4G_ARMS][C4G_AXES_PER_ARM], int x_for_ff)
{
    unsigned arm, ax;
    for (arm = 0; arm < C4G_ARMS; arm++) {
        printf("%s ARM%u:\n ", title, arm + 1);
        for (ax = 0; ax < 9; ax++) {   /* the figure prints 9 of the 10 values */
            if (x_for_ff && v[arm][ax] == C4G_OPEN_AX_NONE) {
                printf(" X");
            } else {
                printf(" %d", (int)v[arm][ax] + (x_for_ff ? 1 : 0));
            }
        }
        printf("\n");
    }
}

static void print_arm_floats(const char *title, float v[C4G_ARMS][C4G_AXES_PER_ARM])
{
    unsigned arm, ax;
    for (arm = 0; arm < C4G_ARMS; arm++) {
        printf("%s ARM%u:\n ", title, arm + 1);
        for (ax = 0; ax < 9; ax++) {
            printf(" %f", (double)v[arm][ax]);
        }
        printf("\n");
    }
}

int main(void)
{
    static c4g_session_t s;
    c4g_init_t init;
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t tx;
    c4g_rx_result_t r;
    c4g_timing_t t;
    uint8_t buf[C4G_INIT_SIZE], out[C4G_INIT_SIZE];
    size_t len, n;
    uint64_t now = 1000000000ULL;
    int32_t num;
    unsigned i, bad = 0;

    bad += c4gsim_fig10_1(&init) != C4G_OK;
    bad += c4g_session_init(&s, NULL) != C4G_OK;
    for (num = 1; num <= 12; num++) {            /* 9 syncs, init (10), 2 syncs */
        if (num == C4G_INIT_NUM) {
            bad += c4g_init_encode(&init, buf, sizeof buf, &len) != C4G_OK;
        } else {
            memset(buf, 0, C4G_SYNC_REPLY_SIZE);
            buf[0] = (uint8_t)num;
            len = C4G_SYNC_REPLY_SIZE;
        }
        bad += c4g_session_rx(&s, buf, len, now, &r) != C4G_OK;
        bad += c4g_session_reply(&s, NULL, out, sizeof out, &n) != C4G_OK;
        now += 2000000;
    }
    printf("Protocol number: %d\nTotal amount of packet fields: %d\n", (int)s.init.num,
           (int)s.init.n_field_pck);
    printf("Total amount of axis fields: %d\nTotal amount of open modality axes: %d\n",
           (int)s.init.n_field_ax, (int)s.init.n_ax_open);
    print_arm_ints("Axes modalities", s.init.open_mask, 0);
    print_arm_ints("Open axes indexes", s.init.open_ax, 1);
    print_arm_floats("Calibration constants", s.init.cal_data);
    print_arm_floats("Current saturation values", s.init.az_lim);
    print_arm_floats("Transmission ratio values", s.init.tx_rate);
    print_arm_floats("Influence coefficients values", s.init.ax_info);
    print_arm_floats("Following error values", s.init.follow_error);
    printf("Ts: %d [msec]\nSoftware Version: %d.%d.%d\n\n", (int)s.init.period_ms,
           (int)s.init.version_major, (int)s.init.version_minor, (int)s.init.version_build);

    memset(&p, 0, sizeof p);
    p.n_axes = s.map.n_axes;
    p.infpar = C4G_STS_MOVING;                    /* drives on, ARM 1 */
    for (i = 0; i < 1000; i++) {                  /* 2 s at 2 ms */
        num = 13 + (int32_t)i;
        p.num = num & C4G_NUM_MAX;
        p.ax[0].actual_pos = 0.001f * (float)i;
        now += 2000000 + ((i % 7 == 0) ? 150000 : 0) - ((i % 11 == 0) ? 90000 : 0);
        if (i == 500 || i == 501) {
            continue;                             /* two packets lost on the wire */
        }
        bad += c4g_ctrl_encode(&p, buf, sizeof buf, &len) != C4G_OK;
        if (i == 700) {
            len -= 1;                             /* a truncated datagram */
        }
        bad += c4g_session_rx(&s, buf, len, now, &r) != C4G_OK;
        if (r.kind == C4G_RX_CYCLIC && (i % 2) == 0) {
            /* a reply the program builds (here the neutral one), encoded and checked */
            bad += c4g_pc_reply_neutral(r.pkt, &tx) != C4G_OK;
            bad += c4g_session_reply(&s, &tx, out, sizeof out, &n) != C4G_OK;
            bad += c4g_session_sent(&s, now + 40000 + (i % 13) * 1000) != C4G_OK;
        } else if (r.kind == C4G_RX_CYCLIC) {
            /* the same bytes, encoded straight from the packet the session checked */
            bad += c4g_session_reply_neutral(&s, out, sizeof out, &n) != C4G_OK;
            bad += c4g_session_sent(&s, now + 40000 + (i % 13) * 1000) != C4G_OK;
        }
    }
    bad += c4g_session_timing(&s, &t) != C4G_OK;
    printf("Session counters: rx %llu, tx %llu, sync %llu, init %llu, cyclic %llu\n",
           (unsigned long long)s.counters.rx, (unsigned long long)s.counters.tx,
           (unsigned long long)s.counters.sync, (unsigned long long)s.counters.init,
           (unsigned long long)s.counters.cyclic);
    printf("  NUM gaps %llu (%llu packets never seen), duplicates %llu, out of order %llu\n",
           (unsigned long long)s.counters.gaps, (unsigned long long)s.counters.missed,
           (unsigned long long)s.counters.duplicates, (unsigned long long)s.counters.out_of_order);
    printf("  malformed %llu (length %llu)\n", (unsigned long long)s.counters.malformed_total,
           (unsigned long long)s.counters.malformed[C4G_MAL_LENGTH]);
    printf("Nominal Inter-Packets Period = %.9f s\n", (double)t.nominal_period_ns / 1e9);
    printf("Worst cycle time = %.9f s\n", (double)t.worst_cycle_ns / 1e9);
    printf("Measured Inter-Packets Period range = [%+.9f; %+.9f] s\n", (double)t.min_inter_ns / 1e9,
           (double)t.max_inter_ns / 1e9);
    printf("Jitter range = [%+.9f; %+.9f] s\n", (double)t.min_jitter_ns / 1e9,
           (double)t.max_jitter_ns / 1e9);
    printf("Percentage jitter range = [%+.3f; %+.3f] %%\n", t.min_jitter_pct, t.max_jitter_pct);

    bad += s.counters.init != 1 || s.counters.sync != 11 || s.counters.cyclic != 997;
    bad += s.counters.gaps != 2 || s.counters.missed != 3 || s.counters.malformed_total != 1;
    bad += t.worst_cycle_ns != 52000 || t.max_jitter_ns != 4000000 || t.min_jitter_ns != -90000;
    printf("%s\n", bad ? "session_walkthrough: UNEXPECTED RESULT" : "session_walkthrough: as expected");
    return bad ? 1 : 0;
}
