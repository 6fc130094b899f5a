/* SPDX-License-Identifier: MIT */
/* Prints "FRAME HEX" for every UDP datagram c4g-replay's capture reader delivers (the oracle
 * test compares them with tshark's udp.payload), and "FRAME bad" for a damaged frame.
 * Built by `make e2e-helpers` with tools/c4g-replay/capture.c and libpcap. */
#include "capture.h"

#include <stdio.h>

int main(int argc, char **argv)
{
    char err[512];
    cap_t *c;
    cap_pkt_t p;
    cap_res_t r;
    if (argc != 2) {
        fprintf(stderr, "usage: cap_payloads FILE\n");
        return 2;
    }
    c = cap_open(argv[1], err, sizeof err);
    if (c == NULL) {
        fprintf(stderr, "cap_payloads: %s\n", err);
        return 2;
    }
    while ((r = cap_next(c, &p, err, sizeof err)) != CAP_END && r != CAP_FATAL) {
        size_t i;
        if (r == CAP_BAD) {
            printf("%llu bad\n", (unsigned long long)cap_counts(c)->frames);
            continue;
        }
        if (r != CAP_DATAGRAM) {
            continue;
        }
        printf("%llu ", (unsigned long long)p.frame);
        for (i = 0U; i < p.len; i++) {
            printf("%02x", (unsigned)p.payload[i]);
        }
        putchar('\n');
    }
    cap_close(c);
    return (r == CAP_FATAL) ? 1 : 0;
}
