/* SPDX-License-Identifier: MIT */
/* libFuzzer: the CANopen channel INI (lib/host/c4gh_coconfig.c through the shared INI
 * layer and inih). Invariants: an error is one well-formed "PATH:..." message; an accepted
 * file is a network the library's master accepts. */
#include "fuzz_text.h"
#include "c4gh_coconfig.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static c4gh_co_config_t c;
static c4g_co_master_t m;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[512];
    c4gh_tf_file_t f;
    char *buf = fuzz_copy(data, size);
    if (buf == NULL) {
        return 0;
    }
    c4gh_tf_open_mem(&f, "coc0.ini", buf, size);
    memset(err, 0x55, sizeof err);
    if (c4gh_co_config_parse(&c, &f, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "coc0.ini");
        free(buf);
        return 0;
    }
    if (c4g_co_master_init(&m, &c.net) != C4G_OK || c.net.n_nodes < 1 ||
        c.net.n_nodes > C4G_CO_MAX_NODES) {
        abort();
    }
    free(buf);
    return 0;
}
