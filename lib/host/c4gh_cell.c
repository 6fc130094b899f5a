/* SPDX-License-Identifier: MIT */
/* Shared helpers of cell-sim and cell-cli (see cell_common.h). */
#include "c4gh_cell.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static const char *const dev_names[C4GH_CELL_DEVICES] = {"robot", "platform", "conditioning"};

const char *c4gh_cell_dev_name(int dev)
{
    return (dev >= 0 && dev < C4GH_CELL_DEVICES) ? dev_names[dev] : "?";
}

unsigned c4gh_cell_dev_default_port(int dev)
{
    return 2001U + (unsigned)dev;
}

int c4gh_cell_dev_parse(const char *s)
{
    size_t n = strlen(s);
    int found = -1;
    if (n == 0) {
        return -1;
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (strncasecmp(s, dev_names[d], n) == 0) {
            if (found >= 0) {
                return -1; /* ambiguous */
            }
            found = d;
        }
    }
    return found;
}

int c4gh_cell_parse_uint(const char *s, unsigned long max, unsigned long *out)
{
    char *end = NULL;
    unsigned long v;
    if (s == NULL || *s == '\0' || *s == '-' || *s == '+') {
        return -1;
    }
    errno = 0;
    v = strtoul(s, &end, 10);
    if (errno != 0 || *end != '\0' || v > max) {
        return -1;
    }
    *out = v;
    return 0;
}

int c4gh_cell_parse_double(const char *s, double *out)
{
    char *end = NULL;
    double v;
    if (s == NULL || *s == '\0') {
        return -1;
    }
    errno = 0;
    v = strtod(s, &end);
    if (errno != 0 || *end != '\0' || v != v) {
        return -1;
    }
    *out = v;
    return 0;
}

int c4gh_cell_parse_hostport(const char *s, char *host, size_t host_cap, unsigned *port)
{
    const char *colon = strrchr(s, ':');
    size_t hl = colon ? (size_t)(colon - s) : strlen(s);
    if (hl >= host_cap) {
        return -1;
    }
    if (colon != NULL) {
        unsigned long p;
        if (c4gh_cell_parse_uint(colon + 1, 65535UL, &p) != 0 || p == 0) {
            return -1;
        }
        *port = (unsigned)p;
    }
    if (hl > 0) {
        memcpy(host, s, hl);
        host[hl] = '\0';
    } else if (colon == NULL) {
        return -1;
    }
    return 0;
}

int c4gh_cell_tcp_listen(const char *addr, unsigned port, int backlog)
{
    struct sockaddr_in sa;
    int one = 1;
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) {
        return -1;
    }
    (void)setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)port);
    if (inet_pton(AF_INET, addr, &sa.sin_addr) != 1 ||
        bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0 || listen(fd, backlog) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    (void)fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    return fd;
}

int c4gh_cell_tcp_connect(const char *host, unsigned port, int timeout_ms, const char **err)
{
    struct addrinfo hints, *res = NULL;
    char ps[16];
    int fd, rc, one = 1;
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_STREAM;
    snprintf(ps, sizeof ps, "%u", port);
    if (getaddrinfo(host, ps, &hints, &res) != 0 || res == NULL) {
        *err = "cannot resolve host";
        return -1;
    }
    fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) {
        freeaddrinfo(res);
        *err = "socket() failed";
        return -1;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    rc = connect(fd, res->ai_addr, res->ai_addrlen);
    freeaddrinfo(res);
    if (rc != 0 && errno != EINPROGRESS) {
        *err = (errno == ECONNREFUSED) ? "connection refused" : strerror(errno);
        close(fd);
        return -1;
    }
    if (rc != 0) {
        struct pollfd p = {fd, POLLOUT, 0};
        int soerr = 0;
        socklen_t sl = sizeof soerr;
        rc = poll(&p, 1, timeout_ms);
        if (rc == 0) {
            *err = "connect timeout";
            close(fd);
            return -1;
        }
        getsockopt(fd, SOL_SOCKET, SO_ERROR, &soerr, &sl);
        if (rc < 0 || soerr != 0) {
            *err = (soerr == ECONNREFUSED) ? "connection refused" : strerror(soerr ? soerr : errno);
            close(fd);
            return -1;
        }
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    *err = NULL;
    return fd;
}

void c4gh_cell_peer_string(int fd, char *buf, size_t cap)
{
    struct sockaddr_in a;
    socklen_t al = sizeof a;
    char ip[INET_ADDRSTRLEN];
    if (getpeername(fd, (struct sockaddr *)&a, &al) != 0 || a.sin_family != AF_INET ||
        inet_ntop(AF_INET, &a.sin_addr, ip, sizeof ip) == NULL) {
        snprintf(buf, cap, "?");
        return;
    }
    snprintf(buf, cap, "%s:%u", ip, (unsigned)ntohs(a.sin_port));
}
