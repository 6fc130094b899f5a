/* SPDX-License-Identifier: MIT */
/* udp_echo: the latency baseline for bench/server_latency.sh. A bare blocking UDP loop
 * that sends every datagram back with NUM + 1 (so the controller stub accepts it) and does
 * nothing else: no decoding, no session, no safety filter. Same socket calls as c4g-server. */
#include <arpa/inet.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

int main(int argc, char **argv)
{
    struct sockaddr_in me, peer;
    unsigned char b[2048];
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    memset(&me, 0, sizeof me);
    me.sin_family = AF_INET;
    me.sin_port = htons((uint16_t)(argc > 1 ? atoi(argv[1]) : 31080));
    if (fd < 0 || bind(fd, (struct sockaddr *)&me, sizeof me) != 0) {
        perror("udp_echo: bind");
        return 1;
    }
    for (;;) {
        socklen_t pl = sizeof peer;
        const ssize_t n = recvfrom(fd, b, sizeof b, 0, (struct sockaddr *)&peer, &pl);
        uint32_t num;
        if (n < 4) {
            continue;
        }
        num = (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) | ((uint32_t)b[3] << 24);
        if (n == 12 && num == 0xFFFFFFFFU) {
            return 0; /* stop request */
        }
        num = (num >= 0x7FFFU) ? 1U : num + 1U;
        b[0] = (unsigned char)num; b[1] = (unsigned char)(num >> 8);
        b[2] = (unsigned char)(num >> 16); b[3] = (unsigned char)(num >> 24);
        sendto(fd, b, (size_t)n, 0, (struct sockaddr *)&peer, pl);
    }
}
