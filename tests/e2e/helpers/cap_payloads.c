/* SPDX-License-Identifier: MIT */
/* Prints "FRAME HEX" for every UDP datagram c4g-replay's capture reader delivers (the oracle
 * test compares them with tshark's udp.payload), and "FRAME bad" for a damaged frame.
 * Built by `make e2e-helpers` with the host archive's capture reader and libpcap. */
#include "c4gh_capture.h"

#include <stdio.h>

int main(int argc, char **argv)
{
    char err[512];
    c4gh_cap_t *c;
    c4gh_cap_pkt_t p;
    c4gh_cap_res_t r;
    if (argc != 2) {
        fprintf(stderr, "usage: cap_payloads FILE\n");
        return 2;
    }
    c = c4gh_cap_open(argv[1], err, sizeof err);
    if (c == NULL) {
        fprintf(stderr, "cap_payloads: %s\n", err);
        return 2;
    }
    while ((r = c4gh_cap_next(c, &p, err, sizeof err)) != C4GH_CAP_END && r != C4GH_CAP_FATAL) {
        size_t i;
        if (r == C4GH_CAP_BAD) {
            printf("%llu bad\n", (unsigned long long)c4gh_cap_counts(c)->frames);
            continue;
        }
        if (r != C4GH_CAP_DATAGRAM) {
            continue;
        }
        printf("%llu ", (unsigned long long)p.frame);
        for (i = 0U; i < p.len; i++) {
            printf("%02x", (unsigned)p.payload[i]);
        }
        putchar('\n');
    }
    c4gh_cap_close(c);
    return (r == C4GH_CAP_FATAL) ? 1 : 0;
}
