/* SPDX-License-Identifier: MIT */
/* Test-only UDP flood for tests/e2e/test_server_flood.py: zero-filled datagrams of SIZE bytes
 * from SRC (any port) to 127.0.0.1:PORT, as fast as one process can send them, for SECONDS
 * (or until SIGTERM). Prints "sent=N seconds=S rate=R" (datagrams per second).
 * Usage: flood PORT SRC SIZE SECONDS */
#include <arpa/inet.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static volatile sig_atomic_t g_stop;

static void on_term(int sig)
{
    (void)sig;
    g_stop = 1;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    static unsigned char buf[2048];
    struct sockaddr_in src, dst;
    unsigned long long sent = 0ULL;
    double t0, t;
    long size;
    double secs;
    int fd;
    if (argc != 5) {
        fprintf(stderr, "usage: flood PORT SRC SIZE SECONDS\n");
        return 2;
    }
    size = strtol(argv[3], NULL, 10);
    secs = strtod(argv[4], NULL);
    if (size < 0 || size > (long)sizeof buf || !(secs > 0.0 && secs < 600.0)) {
        fprintf(stderr, "flood: SIZE 0..2048, SECONDS in (0, 600)\n");
        return 2;
    }
    signal(SIGTERM, on_term);
    memset(&src, 0, sizeof src);
    src.sin_family = AF_INET;
    memset(&dst, 0, sizeof dst);
    dst.sin_family = AF_INET;
    dst.sin_port = htons((unsigned short)strtol(argv[1], NULL, 10));
    if (inet_pton(AF_INET, argv[2], &src.sin_addr) != 1 ||
        inet_pton(AF_INET, "127.0.0.1", &dst.sin_addr) != 1) {
        fprintf(stderr, "flood: bad address\n");
        return 2;
    }
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0 || bind(fd, (struct sockaddr *)&src, sizeof src) != 0) {
        fprintf(stderr, "flood: socket/bind %s: %s\n", argv[2], strerror(errno));
        return 1;
    }
    t0 = now_s();
    t = t0;
    while (!g_stop && t - t0 < secs) {
        unsigned k;
        for (k = 0U; k < 256U; k++) {
            if (sendto(fd, buf, (size_t)size, 0, (struct sockaddr *)&dst, sizeof dst) == (ssize_t)size) {
                sent++;
            }
        }
        t = now_s();
    }
    printf("sent=%llu seconds=%.3f rate=%.0f\n", sent, t - t0, (double)sent / (t - t0));
    close(fd);
    return 0;
}
