/* SPDX-License-Identifier: MIT */
/* The server core's per-datagram step (tools/c4g-server/srv_core.c), the code c4g-server runs
 * on its socket and c4g-replay rerun on a capture: a controller's start-up and cyclic
 * packets, built with the library's encoders, give the field library's replies; the same
 * packets at the same times give the same bytes; the configuration reaches the replies;
 * --skip-replies holds a reply back. The server archive is linked. */
#define TH_FIG10_1
#include "test_helpers.h"

#include <math.h>

#include "c4gh_textfile.h"
#include "c4gh_cli.h"
#include "controllers.h"
#include "c4gh_ffmodel.h"
#include "c4gh_hist.h"
#include "srv_core.h"

#define MS 1000000ULL
#define N_AX 6U
#define N_MODE0 20U
#define N_MODE4 40U
#define N_PKT (9U + 1U + 2U + N_MODE0 + N_MODE4)
#define FIRST_CYCLIC 12U /* index of the first cyclic packet in the sequence */

typedef struct reply {
    bool send;
    bool skipped;
    c4g_rx_kind_t kind;
    size_t len;
    uint8_t bytes[C4G_INIT_SIZE];
} reply_t;

typedef struct run {
    reply_t r[N_PKT];
    unsigned log_lines;
    bool saw_init_line;
    unsigned ff_warnings;
    unsigned rigid_lines;       /* "axis N: mode 9 feedforward: model rigid (...)" */
} run_t;

static srv_t g_srv; /* static: large */
static run_t g_a, g_b;

/* A logger that only counts: the core formats nothing itself. */
static void count_log(void *ctx, uint64_t t_ns, const char *fmt, va_list ap)
{
    run_t *run = ctx;
    char line[256];
    (void)t_ns;
    (void)vsnprintf(line, sizeof line, fmt, ap);
    run->log_lines++;
    if (strncmp(line, "init packet: 6 open axes, period 2 ms", 37) == 0) {
        run->saw_init_line = true;
    }
    if (strcmp(line, "warning: feedforward m.ini: model identified at a 1 ms period, the "
                     "controller runs at 2 ms; applied anyway") == 0) {
        run->ff_warnings++;
    }
    if (strstr(line, ": mode 9 feedforward: model rigid (arm 1's rigid-body model, joint ") != NULL) {
        run->rigid_lines++;
    }
}

/* Packet k of the sequence: 9 sync (NUM 1..9), the figure-10.1 init packet (NUM 10), 2
 * sync (NUM 11, 12), N_MODE0 cyclic packets in mode 0 then N_MODE4 in mode 4, the arm
 * standing at 0.2 turns (the SMP+ target follows the PC's mode-4 target one tick late). */
static size_t packet(uint32_t k, const float *last_target, uint8_t *buf, size_t cap)
{
    const int32_t num = (int32_t)k + 1;
    c4g_ctrl_packet_t p;
    size_t len = 0U;
    uint32_t i;
    if (k == 9U) {
        c4g_init_t init;
        assert_int_equal(c4gsim_fig10_1(&init), C4G_OK);
        assert_int_equal(c4g_init_encode(&init, buf, cap, &len), C4G_OK);
        assert_int_equal(len, C4G_INIT_SIZE);
        assert_memory_equal(buf, th_fig, C4G_INIT_SIZE); /* the manual's bytes */
        return len;
    }
    memset(&p, 0, sizeof p);
    p.num = num;
    p.n_axes = N_AX;
    for (i = 0U; i < N_AX; i++) {
        p.ax[i].mode = (k >= FIRST_CYCLIC + N_MODE0) ? C4G_MODE_4 : 0;
        /* the reference it applied: where it stood in mode 0, then the PC's last target */
        p.ax[i].target_pos = (p.ax[i].mode == C4G_MODE_4) ? last_target[i] : 0.2f;
        p.ax[i].actual_pos = p.ax[i].target_pos;
    }
    assert_int_equal(c4g_ctrl_encode(&p, buf, cap, &len), C4G_OK);
    return len;
}

/* The whole sequence through a fresh core on @p cfg, 2 ms apart; every reply kept. */
static void run_sequence(const srv_config_t *cfg, run_t *run, bool logged)
{
    c4g_endpoint_t ctl;
    uint64_t t = 1000U * MS;
    float last_target[N_AX];
    uint32_t k;
    for (k = 0U; k < N_AX; k++) {
        last_target[k] = 0.2f;
    }
    memset(run, 0, sizeof *run);
    memset(&ctl, 0, sizeof ctl);
    ctl.addr_len = 4U;
    ctl.addr[0] = 127U;
    ctl.addr[3] = 1U;
    ctl.port = 3600U;
    assert_int_equal(srv_init(&g_srv, cfg, logged ? count_log : NULL, run), C4G_OK);
    g_srv.t0_ns = t;
    for (k = 0U; k < N_PKT; k++) {
        uint8_t in[C4G_INIT_SIZE];
        reply_t *r = &run->r[k];
        srv_verdict_t v;
        const size_t n = packet(k, last_target, in, sizeof in);
        t += 2U * MS;
        assert_int_equal(srv_process(&g_srv, in, n, &ctl, t, r->bytes, sizeof r->bytes, &r->len,
                                     &v), C4G_OK);
        assert_int_equal(v.stop, SRV_STOP_NONE);
        assert_false(v.freeze);
        r->send = v.send;
        r->skipped = v.skipped;
        r->kind = v.kind;
        if (v.send) {
            srv_sent(&g_srv, t + 50000U);
        }
        if (v.send && v.kind == C4G_RX_CYCLIC) {
            c4g_pc_packet_t pc;
            uint32_t i;
            assert_int_equal(c4g_pc_decode(r->bytes, r->len, N_AX, &pc, NULL), C4G_OK);
            for (i = 0U; i < N_AX; i++) {
                if (pc.ax[i].mode == C4G_MODE_4) {
                    last_target[i] = pc.ax[i].target_pos;
                }
            }
        }
    }
}

static void config(srv_config_t *cfg, const char *sine, const char *skip)
{
    char err[256];
    srv_config_default(cfg);
    assert_int_equal(srv_config_apply(cfg, "sine", sine, 0, err, sizeof err), 0);
    if (skip != NULL) {
        assert_int_equal(srv_config_apply(cfg, "skip-replies", skip, 0, err, sizeof err), 0);
    }
}

static float reply_d1(const reply_t *r, uint32_t axis)
{
    c4g_pc_packet_t pc;
    assert_int_equal(c4g_pc_decode(r->bytes, r->len, N_AX, &pc, NULL), C4G_OK);
    return pc.ax[axis].target_pos;
}

static void test_handshake_and_cyclic_replies(void **state)
{
    static srv_config_t cfg;
    uint32_t k;
    (void)state;
    config(&cfg, "0.25,5", NULL);
    run_sequence(&cfg, &g_a, true);
    for (k = 0U; k < N_PKT; k++) {
        const reply_t *r = &g_a.r[k];
        const uint32_t num = th_get_u32(r->bytes);
        assert_true(r->send);
        if (k == 9U) {
            assert_int_equal(r->kind, C4G_RX_INIT);
            assert_int_equal(r->len, C4G_INIT_SIZE);
            assert_int_equal(num, 11U); /* NUM 10 + 1 */
            assert_memory_equal(&r->bytes[4], &th_fig[4], C4G_INIT_SIZE - 4U);
        } else if (k < FIRST_CYCLIC) {
            assert_int_equal(r->kind, C4G_RX_SYNC);
            assert_int_equal(r->len, C4G_SYNC_REPLY_SIZE);
            assert_int_equal(num, k + 2U);
        } else {
            c4g_pc_packet_t pc;
            const int32_t mode = (k >= FIRST_CYCLIC + N_MODE0) ? C4G_MODE_4 : 0;
            assert_int_equal(r->kind, C4G_RX_CYCLIC);
            assert_int_equal(r->len, C4G_CYCLIC_SIZE(N_AX));
            assert_int_equal(c4g_pc_decode(r->bytes, r->len, N_AX, &pc, NULL), C4G_OK);
            assert_int_equal(pc.num, (int32_t)k + 2); /* NUM + 1 */
            assert_int_equal(pc.ax[0].mode, mode);
            if (mode == 0) {
                assert_true(pc.ax[0].target_pos == 0.0f);
            }
        }
    }
    /* mode 4: absolute targets from where the arm stood, moving away from it */
    assert_float_equal(reply_d1(&g_a.r[FIRST_CYCLIC + N_MODE0], 0U), 0.2, 1e-6);
    assert_true(reply_d1(&g_a.r[N_PKT - 1U], 0U) > 0.25f);
    assert_int_equal(srv_counters(&g_srv)->cyclic, N_MODE0 + N_MODE4);
    assert_int_equal(g_srv.stats.inits, 1U);
    assert_int_equal(g_srv.stats.skipped, 0U);
    assert_int_equal(g_srv.stats.neutral_replies, 0U);
    assert_int_equal(g_srv.stats.encode_errors, 0U);
    assert_true(g_a.saw_init_line); /* log lines reach the caller's logger */
}

/* Replies the loop answers with its fallback (every axis holds) are neutral_replies, not
 * encode_errors: the encoder refused none of them; and each counts, whether the loop
 * prepared the fallback with the packet (no engine) or at the reply. The control engine is taken off after
 * the init packet, as when it refuses one (the loop then answers every cyclic packet with
 * the fallback). */
static void test_neutral_replies_counted(void **state)
{
    static srv_config_t cfg;
    c4g_endpoint_t ctl;
    uint64_t t = 1000U * MS;
    float last_target[N_AX];
    uint32_t k, cyclic = 0U;
    (void)state;
    config(&cfg, "0.25,5", NULL);
    for (k = 0U; k < N_AX; k++) {
        last_target[k] = 0.2f;
    }
    memset(&ctl, 0, sizeof ctl);
    ctl.addr_len = 4U;
    ctl.addr[0] = 127U;
    ctl.port = 3600U;
    assert_int_equal(srv_init(&g_srv, &cfg, NULL, NULL), C4G_OK);
    for (k = 0U; k < FIRST_CYCLIC + 20U; k++) {
        uint8_t in[C4G_INIT_SIZE], out[C4G_INIT_SIZE];
        size_t len = 0U;
        srv_verdict_t v;
        const size_t n = packet(k, last_target, in, sizeof in);
        if (k == FIRST_CYCLIC) {
            g_srv.loop.engine_ready = 0U; /* test hook: the engine holds no init packet */
        }
        t += 2U * MS;
        assert_int_equal(srv_process(&g_srv, in, n, &ctl, t, out, sizeof out, &len, &v), C4G_OK);
        assert_true(v.send);
        srv_sent(&g_srv, t + 50000U);
        cyclic += (v.kind == C4G_RX_CYCLIC) ? 1U : 0U;
    }
    assert_int_equal(cyclic, 20U);
    assert_int_equal(g_srv.stats.neutral_replies, 20U);
    assert_int_equal(g_srv.stats.encode_errors, 0U);
    assert_int_equal(srv_loop_counters(&g_srv)->neutral_replies, 20U);
}

static void test_same_packets_same_replies(void **state)
{
    static srv_config_t cfg;
    uint32_t k;
    (void)state;
    config(&cfg, "0.25,5", NULL);
    run_sequence(&cfg, &g_a, true);
    run_sequence(&cfg, &g_b, false); /* a fresh core, and no logger */
    for (k = 0U; k < N_PKT; k++) {
        assert_int_equal(g_a.r[k].send, g_b.r[k].send);
        assert_int_equal(g_a.r[k].len, g_b.r[k].len);
        assert_memory_equal(g_a.r[k].bytes, g_b.r[k].bytes, g_a.r[k].len);
    }
    assert_int_equal(g_b.log_lines, 0U);
}

static void test_amplitude_reaches_mode4_replies(void **state)
{
    static srv_config_t small, large;
    uint32_t k, differ = 0U;
    (void)state;
    config(&small, "0.25,5", NULL);
    config(&large, "0.5,5", NULL);
    run_sequence(&small, &g_a, false);
    run_sequence(&large, &g_b, false);
    for (k = 0U; k < FIRST_CYCLIC + N_MODE0; k++) { /* handshake and mode 0: the same */
        assert_int_equal(g_a.r[k].len, g_b.r[k].len);
        assert_memory_equal(g_a.r[k].bytes, g_b.r[k].bytes, g_a.r[k].len);
    }
    for (k = FIRST_CYCLIC + N_MODE0 + 1U; k < N_PKT; k++) {
        const float a = reply_d1(&g_a.r[k], 0U), b = reply_d1(&g_b.r[k], 0U);
        assert_true(b - 0.2f > a - 0.2f); /* twice the offset from the start */
        differ++;
    }
    assert_int_equal(differ, N_MODE4 - 1U);
}

static void test_skip_replies_not_sent(void **state)
{
    static srv_config_t cfg;
    uint32_t k;
    (void)state;
    config(&cfg, "0.25,5", "5,3"); /* cyclic packets 5, 6, 7 of the session */
    run_sequence(&cfg, &g_b, false);
    for (k = 0U; k < N_PKT; k++) {
        const bool held = k >= FIRST_CYCLIC + 4U && k < FIRST_CYCLIC + 7U;
        assert_int_equal(g_b.r[k].send, !held);
        assert_int_equal(g_b.r[k].skipped, held);
        if (held) {
            assert_int_equal(g_b.r[k].len, 0U);
        }
    }
    assert_int_equal(g_srv.stats.skipped, 3U);
    /* the held-back ticks still ran: the replies after them are the unskipped run's */
    config(&cfg, "0.25,5", NULL);
    run_sequence(&cfg, &g_a, false);
    for (k = FIRST_CYCLIC + 7U; k < N_PKT; k++) {
        assert_memory_equal(g_a.r[k].bytes, g_b.r[k].bytes, g_a.r[k].len);
    }
}

/* Mode 9 with an identified model on axis 2: the SMP+ targets give v, a and, through the
 * init packet's kinematics, the link angle one tick ahead; the core counts the model's
 * ticks and clamps and warns once about a model identified at another period. */
#define N9 10U
#define D2_0 0.001f
#define D2_1 0.002f /* from mode-9 packet 5: a = 0.001 / dt^2 = 250 turns/s^2 */

static float mode9_d1(uint32_t j)
{
    return 0.2f + D2_0 * (float)(j < 5U ? j : 5U) + D2_1 * (float)(j < 5U ? 0U : j - 5U);
}

static void run_mode9(const srv_config_t *cfg, run_t *run, float d5[N9][N_AX])
{
    c4g_endpoint_t ctl;
    uint64_t t = 1000U * MS;
    uint32_t k, i;
    memset(run, 0, sizeof *run);
    memset(&ctl, 0, sizeof ctl);
    ctl.addr_len = 4U;
    ctl.addr[0] = 127U;
    ctl.addr[3] = 1U;
    ctl.port = 3600U;
    assert_int_equal(srv_init(&g_srv, cfg, count_log, run), C4G_OK);
    g_srv.t0_ns = t;
    for (k = 0U; k < FIRST_CYCLIC + 5U + N9; k++) {
        uint8_t in[C4G_INIT_SIZE], out[C4G_INIT_SIZE];
        size_t n, len = 0U;
        srv_verdict_t v;
        if (k < FIRST_CYCLIC + 5U) {
            static const float at[N_AX] = {0.2f, 0.2f, 0.2f, 0.2f, 0.2f, 0.2f};
            n = packet(k, at, in, sizeof in); /* handshake, 5 packets in mode 0 */
        } else {
            const uint32_t j = k - FIRST_CYCLIC - 5U;
            c4g_ctrl_packet_t p;
            memset(&p, 0, sizeof p);
            p.num = (int32_t)k + 1;
            p.n_axes = N_AX;
            for (i = 0U; i < N_AX; i++) {
                p.ax[i].mode = C4G_MODE_9;
                p.ax[i].target_pos = mode9_d1(j);
                p.ax[i].target_vel = (j < 5U) ? D2_0 : D2_1;
                p.ax[i].actual_pos = p.ax[i].target_pos;
            }
            assert_int_equal(c4g_ctrl_encode(&p, in, sizeof in, &n), C4G_OK);
        }
        t += 2U * MS;
        assert_int_equal(srv_process(&g_srv, in, n, &ctl, t, out, sizeof out, &len, &v), C4G_OK);
        assert_true(v.send);
        srv_sent(&g_srv, t + 50000U);
        if (k >= FIRST_CYCLIC + 5U) {
            c4g_pc_packet_t pc;
            assert_int_equal(c4g_pc_decode(out, len, N_AX, &pc, NULL), C4G_OK);
            for (i = 0U; i < N_AX; i++) {
                assert_int_equal(pc.ax[i].mode, C4G_MODE_9);
                d5[k - FIRST_CYCLIC - 5U][i] = pc.ax[i].current_add;
            }
        }
    }
}

static void test_mode9_model(void **state)
{
    static srv_config_t cfg;
    static float d5[N9][N_AX];
    c4g_init_t init;
    ctlr_ff_t *p;
    uint32_t j;
    (void)state;
    assert_int_equal(c4gsim_fig10_1(&init), C4G_OK);
    srv_config_default(&cfg);
    strcpy(cfg.ff_path[0], "m.ini");
    cfg.n_ff = 1U;
    p = &cfg.ff[0][1];
    p->set = 11;
    p->kind = CTLR_FF_MODEL;
    p->period_ms = 1.0; /* the controller runs at 2 ms */
    p->model.set = 1;
    p->model.ja = 0.01;
    p->model.gb = 50.0;
    p->model.eps = 0.01;
    run_mode9(&cfg, &g_a, d5);
    for (j = 0U; j < N9; j++) {
        /* axis 2 has no wrist coupling: q = 2 pi (D1 + D2 - cal) / TxRate */
        const double qm = (double)mode9_d1(j) + (double)((j < 5U) ? D2_0 : D2_1);
        const double q = 2.0 * 3.14159265358979323846 * (qm - (double)init.cal_data[0][1]) /
                         (double)init.tx_rate[0][1];
        const double a = (j == 5U) ? ((double)D2_1 - (double)D2_0) / (0.002 * 0.002) : 0.0;
        assert_float_equal(d5[j][1], 0.01 * a + 50.0 * sin(q), 1e-5);
        assert_true(d5[j][0] == 0.0f); /* no parameters for axis 1 */
    }
    assert_float_equal(d5[5][1] - d5[4][1], 2.5, 0.01);
    assert_true(g_srv.stats.ff_model_ticks == N9);
    assert_true(g_srv.stats.ff_model_clamped == 0U);
    assert_int_equal(g_a.ff_warnings, 1U);
    /* the acceleration outside the fit's range: clamped to a_max, counted */
    p->model.a_max = 100.0;
    p->period_ms = 2.0;
    run_mode9(&cfg, &g_a, d5);
    assert_float_equal(d5[5][1] - d5[4][1], 1.0, 0.01);
    assert_true(g_srv.stats.ff_model_clamped == 1U);
    assert_int_equal(g_a.ff_warnings, 0U);
}

/* Mode 9 with the arm plant's rigid-body file, axis 1 not driven: each driven axis's D5 is
 * its motor's current of the whole arm's model, evaluated from every axis's D1 + D2 and
 * predicted velocity and acceleration (axis 1's too: its acceleration at the step of D2
 * moves the others through the coupled inertia), before any axis's controller steps. */
static void test_mode9_rigid(void **state)
{
    static srv_config_t cfg;
    static float d5[N9][N_AX];
    static c4gh_ffm_file_t m;
    c4g_init_t init;
    c4g_kin_t kin;
    c4gh_ffr_t r;
    c4gh_ffr_out_t o;
    char err[600];
    const double T = 0.002;
    uint32_t j, l;
    double da = 0.0;
    (void)state;
    assert_int_equal(c4gsim_fig10_1(&init), C4G_OK);
    assert_int_equal(c4g_kin_from_init(&init, 0U, &kin), C4G_OK);
    assert_int_equal(c4gh_ffm_load(FIXTURES_DIR "/server/ff_rigid_example.ini", &m, err, sizeof err), 0);
    assert_int_equal(c4gh_ffr_setup(&r, &m, &kin), 0);
    srv_config_default(&cfg);
    assert_int_equal(srv_config_apply(&cfg, "ff", FIXTURES_DIR "/server/ff_rigid_example.ini", 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&cfg, err, sizeof err), 0);
    cfg.arm[0].axes = 0x3EU; /* axes 2..6 */
    run_mode9(&cfg, &g_a, d5);
    assert_int_equal(g_a.rigid_lines, 5U);
    for (j = 0U; j < N9; j++) {
        double qm[N_AX], vm[N_AX], am[N_AX];
        for (l = 0U; l < N_AX; l++) {
            const double d2 = (double)((j < 5U) ? D2_0 : D2_1);
            am[l] = (j == 5U) ? ((double)D2_1 - (double)D2_0) / (T * T) : 0.0;
            vm[l] = d2 / T + am[l] * T;
            qm[l] = (double)mode9_d1(j) + d2;
        }
        assert_int_equal(c4gh_ffr_current(&r, qm, vm, am, &o), 0);
        assert_true(d5[j][0] == 0.0f); /* not driven */
        for (l = 1U; l < N_AX; l++) {
            if (fabs((double)d5[j][l] - o.cur[l]) > 1e-6 * fmax(1.0, fabs(o.cur[l]))) { /* float D5 */
                fail_msg("tick %u axis %u: D5 %.9g A, the model %.9g A", j, l + 1U, (double)d5[j][l], o.cur[l]);
            }
        }
        if (j == 5U) {
            /* without axis 1's acceleration the others' currents would differ this much */
            am[0] = 0.0;
            vm[0] = (double)D2_1 / T;
            assert_int_equal(c4gh_ffr_current(&r, qm, vm, am, &o), 0);
            for (l = 1U; l < N_AX; l++) {
                da = fmax(da, fabs((double)d5[j][l] - o.cur[l]));
            }
            print_message("without axis 1's acceleration the currents would be off by up to %.3g A\n", da);
        }
    }
    assert_true(da > 1e-4); /* 0.44 mA: far above D5's float resolution here (< 1e-5 A) */
    assert_true(g_srv.stats.ff_model_ticks == 5U * N9);
    assert_true(g_srv.stats.ff_model_clamped == 0U);
    /* the link parameters are checked once, at setup (not on every tick): one that is not
     * finite refuses the setup; the model set up before keeps its own checked copy */
    m.pi[13] = NAN;
    {
        c4gh_ffr_t bad;
        assert_int_equal(c4gh_ffr_setup(&bad, &m, &kin), -1);
    }
    assert_int_equal(r.dyn.checked, C4G_DYN_CHECKED);
    assert_true(isfinite(r.dyn.pi[13]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_handshake_and_cyclic_replies),
        cmocka_unit_test(test_neutral_replies_counted),
        cmocka_unit_test(test_same_packets_same_replies),
        cmocka_unit_test(test_amplitude_reaches_mode4_replies),
        cmocka_unit_test(test_skip_replies_not_sent),
        cmocka_unit_test(test_mode9_model),
        cmocka_unit_test(test_mode9_rigid),
    };
    return cmocka_run_group_tests(tests, th_load_fig, NULL);
}
