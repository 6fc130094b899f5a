/* SPDX-License-Identifier: MIT */
/* libFuzzer: c4g-sim's INI configuration (tools/c4g-sim/config.c through the shared
 * INI layer and inih). Invariants: an error is one well-formed "PATH:..." message; an
 * accepted file leaves 1..20 open axes and every setting inside its range. */
#include "fuzz_text.h"
#include "sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static sim_config_t c;
    char err[512];
    c4gh_tf_file_t f;
    char *buf = fuzz_copy(data, size);
    int a, l, n;
    if (buf == NULL) {
        return 0;
    }
    sim_config_default(&c);
    c4gh_tf_open_mem(&f, "f.ini", buf, size);
    memset(err, 0x55, sizeof err);
    if (sim_config_parse(&c, &f, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.ini");
        free(buf);
        return 0;
    }
    n = sim_config_axes(&c);
    if (n < 1 || n > 20 || c.port < 1U || c.port > 65535U || c.local_port > 65535U ||
        c.period_ms < 1 || c.period_ms > 2 || c.t_cycle1_us < 1U || c.t_cycle1_us > 1000000U ||
        c.max_miss < 1U || c.max_miss > 1000000U || c.check_follow < 0 || c.check_follow > 1 ||
        c.sync_before > 1000U || c.sync_after > 100U ||
        memchr(c.server, '\0', sizeof c.server) == NULL ||
        memchr(c.bind_addr, '\0', sizeof c.bind_addr) == NULL) {
        abort();
    }
    FUZZ_FINITE_IN(c.drive_on_ms, 0.0, 1e5);
    FUZZ_FINITE_IN(c.switch_ms, 0.0, 1e5);
    for (a = 0; a < (int)C4G_ARMS; a++) {
        for (l = 0; l < (int)C4G_AXES_PER_ARM; l++) {
            const c4gsim_axis_params_t *p = &c.ax[a][l];
            FUZZ_FINITE_IN(p->j, 1e-9, 1e3);
            FUZZ_FINITE_IN(p->kt, 1e-6, 1e3);
            FUZZ_FINITE_IN(p->gravity, -1e4, 1e4);
            FUZZ_FINITE_IN(p->az_lim, 0.0, 1e4);
            FUZZ_FINITE_IN(p->vel_filter, 1e-6, 1.0);
            FUZZ_FINITE_IN(p->vmax, 1e-6, 1e5);
            FUZZ_FINITE_IN(p->pos0, -1e6, 1e6);
            if (!c4g_mode_is_known(p->startup_mode)) {
                abort();
            }
        }
    }
    free(buf);
    return 0;
}
