/* SPDX-License-Identifier: MIT */
/* The floor of any libpcap reader, as the baseline of the c4g-replay benchmarks: read
 * every record with pcap_next_ex and touch every captured byte (a sum, printed so the
 * compiler keeps it), nothing else.  pcap_bare FILE */
#include <pcap/pcap.h>
#include <stdint.h>
#include <stdio.h>

int main(int argc, char **argv)
{
    char err[PCAP_ERRBUF_SIZE];
    struct pcap_pkthdr *h;
    const u_char *d;
    pcap_t *p;
    uint64_t frames = 0U, bytes = 0U, sum = 0U;
    int rc;
    if (argc != 2) {
        fprintf(stderr, "usage: pcap_bare FILE\n");
        return 2;
    }
    p = pcap_open_offline(argv[1], err);
    if (p == NULL) {
        fprintf(stderr, "pcap_bare: %s\n", err);
        return 1;
    }
    while ((rc = pcap_next_ex(p, &h, &d)) == 1) {
        uint32_t i;
        for (i = 0U; i < h->caplen; i++) {
            sum += d[i];
        }
        bytes += h->caplen;
        frames++;
    }
    if (rc != PCAP_ERROR_BREAK) {
        fprintf(stderr, "pcap_bare: %s\n", pcap_geterr(p));
        pcap_close(p);
        return 1;
    }
    pcap_close(p);
    printf("%llu frames, %llu bytes, sum %llu\n", (unsigned long long)frames,
           (unsigned long long)bytes, (unsigned long long)sum);
    return 0;
}
