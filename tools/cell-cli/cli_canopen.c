/* SPDX-License-Identifier: MIT */
/* cell-cli canopen (see cli_canopen.h). */
#include "cli_canopen.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "c4gh_textfile.h"

static int connect_to(const char *host, unsigned port)
{
    struct addrinfo hints, *res = NULL;
    char ps[16];
    int fd = -1;
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_STREAM;
    snprintf(ps, sizeof ps, "%u", port);
    if (getaddrinfo(host, ps, &hints, &res) != 0 || res == NULL) {
        return -1;
    }
    fd = socket(res->ai_family, res->ai_socktype, 0);
    if (fd >= 0 && connect(fd, res->ai_addr, res->ai_addrlen) != 0) {
        close(fd);
        fd = -1;
    }
    freeaddrinfo(res);
    return fd;
}

int cli_canopen_run(const char *host, unsigned port, int n, char **words, int timeout_ms)
{
    char line[512] = "";
    char reply[1024];
    char shown[sizeof reply * 4];
    size_t len = 0;
    int fd;
    if (n < 1) {
        fprintf(stderr, "cell-cli: canopen: want a command, e.g. 'canopen CO_RNMT 1' "
                        "(CO_RNMT, CO_ROBJ, CO_WOBJ, CO_SDO, CO_RRPDO, CO_RTPDO, CO_STATE_MAC, "
                        "CO_CHDIAGNO, CO_WSDIAGNO, CO_REMCY, S_NMT, HELP)\n");
        return 2;
    }
    for (int i = 0; i < n; i++) {
        if (strlen(line) + strlen(words[i]) + 2 >= sizeof line) {
            fprintf(stderr, "cell-cli: canopen: command too long\n");
            return 2;
        }
        strcat(line, i ? " " : "");
        strcat(line, words[i]);
    }
    strcat(line, "\n");
    fd = connect_to(host, port);
    if (fd < 0) {
        fprintf(stderr, "cell-cli: canopen: cannot connect to the CANopen shell at %s:%u "
                        "(cell-sim --canopen FILE serves it on the platform port + 10)\n", host, port);
        return 1;
    }
    if (write(fd, line, strlen(line)) != (ssize_t)strlen(line)) {
        close(fd);
        fprintf(stderr, "cell-cli: canopen: send failed\n");
        return 1;
    }
    while (len < sizeof reply - 1) {
        struct pollfd p = {fd, POLLIN, 0};
        ssize_t k;
        if (poll(&p, 1, timeout_ms) <= 0) {
            break;
        }
        k = read(fd, reply + len, sizeof reply - 1 - len);
        if (k <= 0) {
            break;
        }
        len += (size_t)k;
        if (memchr(reply, '\n', len) != NULL) {
            break;
        }
    }
    close(fd);
    reply[len] = '\0';
    if (len == 0 || reply[len - 1] != '\n') {
        fprintf(stderr, "cell-cli: canopen: no reply from %s:%u\n", host, port);
        return 1;
    }
    /* the shell's bytes escaped: none of its escape sequences reaches a terminal */
    c4gh_tf_escape(reply, len - 1, shown, sizeof shown);
    if (strncmp(reply, "ERR", 3) == 0) {
        fprintf(stderr, "cell-cli: canopen: %s\n", len > 4 ? shown + 4 : "");
        return 1;
    }
    printf("%s\n", shown);
    return 0;
}
