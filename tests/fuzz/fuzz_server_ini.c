/* SPDX-License-Identifier: MIT */
/* libFuzzer: c4g-server's INI configuration (tools/c4g-server/srv_opts.c through the shared
 * INI layer and inih). Invariants: an error is one well-formed "PATH:..." message; an
 * accepted file leaves every setting inside its documented range. */
#include <math.h>

#include "fuzz_text.h"
#include "srv_core.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static srv_config_t c;
    char err[512];
    c4gh_tf_file_t f;
    char *buf = fuzz_copy(data, size);
    unsigned a;
    if (buf == NULL) {
        return 0;
    }
    srv_config_default(&c);
    c4gh_tf_open_mem(&f, "f.ini", buf, size);
    memset(err, 0x55, sizeof err);
    if (srv_config_parse_ini(&c, &f, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.ini");
        free(buf);
        return 0;
    }
    if (c.port < 1U || c.port > 65535U || c.prio < 0 || c.prio > 99 || c.cpu < -1 ||
        c.cpu > 1023 || c.late_us < 1U || c.late_us > 1000000U || c.poll_us > 100000U ||
        (c.moni_type != 0 && (c.moni_type < 19 || c.moni_type > 24)) ||
        (c.inject_mode != 0 && c.inject_mode != 505 && c.inject_mode != 508) ||
        c.inject_axis < 0 || c.inject_axis > 19 ||
        memchr(c.bind_addr, '\0', sizeof c.bind_addr) == NULL ||
        memchr(c.ctrl_addr, '\0', sizeof c.ctrl_addr) == NULL) {
        abort();
    }
    FUZZ_FINITE_IN(c.idle_timeout, 0.0, 1e7);
    FUZZ_FINITE_IN(c.max_seconds, 0.0, 1e7);
    FUZZ_FINITE_IN(c.freeze_ms, 0.0, 60000.0);
    for (a = 0U; a < C4G_ARMS; a++) {
        const srv_arm_cfg_t *A = &c.arm[a];
        if (A->axes == 0U || A->axes > 0x3FFU || !isfinite(A->sine_amp) || !(A->sine_freq > 0.0) ||
            !isfinite(A->kp) || !isfinite(A->kd) || !isfinite(A->ki) || A->kp < 0.0 ||
            !(A->duration >= 0.0 && A->duration <= 1e7) || !(A->vel_cycles >= 1.0) ||
            !(A->i_max >= 0.0) || !(A->fe_limit >= 0.0) ||
            memchr(A->traj_path, '\0', sizeof A->traj_path) == NULL) {
            abort();
        }
    }
    free(buf);
    return 0;
}
