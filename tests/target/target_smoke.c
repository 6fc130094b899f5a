/* SPDX-License-Identifier: MIT */
/* Runs on the target (qemu-arm, newlib rdimon): codec and session smoke test on a
 * 32-bit ARM. Prints a closing "N passed, N failed" line; exit status = failures. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <string.h>

static int passed;
static int failed;

static void check(int ok, const char *what)
{
    if (ok) {
        passed++;
    } else {
        failed++;
        printf("FAIL: %s\n", what);
    }
}

int main(void)
{
    static c4g_session_t s;
    c4g_init_t in;
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t tx;
    c4g_rx_result_t r;
    uint8_t init[C4G_INIT_SIZE], buf[C4G_INIT_SIZE], out[C4G_INIT_SIZE];
    size_t len = 0, n = 0;
    FILE *f;

    check(c4gsim_fig10_1(&in) == C4G_OK, "fig10_1");
    check(c4g_init_encode(&in, init, sizeof init, &len) == C4G_OK && len == 1200, "init encode");
    /* the shared vector, read through semihosting: byte-exact on the target too */
    f = fopen(FIXTURE_INIT, "rb");
    if (f != NULL) {
        check(fread(buf, 1, sizeof buf, f) == 1200 && memcmp(buf, init, 1200) == 0, "vector bytes");
        fclose(f);
    }
    check(init[0] == 10 && init[224] == 2 && init[0x226] == 0xc4 && init[0x227] == 0x41,
          "little-endian layout on target");
    check(c4g_session_init(&s, NULL) == C4G_OK, "session init");
    check(c4g_session_rx(&s, init, len, 1000, &r) == C4G_OK && r.kind == C4G_RX_INIT, "rx init");
    check(c4g_session_reply(&s, NULL, out, sizeof out, &n) == C4G_OK && n == 1200 && out[0] == 11,
          "init echo NUM+1");
    memset(&p, 0, sizeof p);
    p.num = 0x7FFF;
    p.n_axes = 6;
    p.ax[2].mode = C4G_MODE_0_DEBUG;
    p.ax[2].target_pos = -3.5f;
    check(c4g_ctrl_encode(&p, buf, sizeof buf, &len) == C4G_OK && len == 228, "ctrl encode");
    s.priv.last_num = 0x7FFE; /* as if the controller had counted up to here: 0x7FFF is newer */
    check(c4g_session_rx(&s, buf, len, 3000, &r) == C4G_OK && r.kind == C4G_RX_CYCLIC, "rx cyclic");
    check(c4g_pc_reply_neutral(r.pkt, &tx) == C4G_OK, "neutral reply");
    check(c4g_session_reply(&s, &tx, out, sizeof out, &n) == C4G_OK && n == 228, "reply");
    check(out[0] == 1 && out[1] == 0, "NUM wraps 0x7FFF -> 1");
    check(memcmp(&out[12 + 72 + 4], &buf[12 + 72 + 4], 4) == 0, "mode 10 copy-back");
    buf[12 + 4 + 3] = 0x7F;
    buf[12 + 4 + 2] = 0xC0; /* NaN in D1 of axis 0 */
    check(c4g_ctrl_decode(buf, len, 6, &p, NULL) == C4G_ERR_NONFINITE, "NaN rejected");
    printf("target_smoke: %d passed, %d failed\n", passed, failed);
    return failed;
}
