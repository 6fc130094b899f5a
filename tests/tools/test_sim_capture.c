/* SPDX-License-Identifier: MIT */
/* c4g-sim --capture: a recorded session played through c4g-sim's own socket, on real UDP
 * sockets on 127.0.0.1 (a silent PC server, a foreign sender), and the options the model
 * has no use for refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <jansson.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include "capture.h"

#define MODE0 FIXTURES_DIR "/replay/mode0.pcap" /* 171 controller packets, the last one 504 */

/* app_t holds the scenario and the histograms: too big for the stack */
static app_t g_app;

/* c4g-sim's main for these arguments: the exit code. */
static int sim_main(const char *const *args)
{
    char *argv[40];
    int argc = 0, done = 1, code;
    while (args[argc] != NULL) {
        argv[argc] = (char *)(uintptr_t)args[argc];
        argc++;
    }
    argv[argc] = NULL;
    memset(&g_app, 0, sizeof g_app);
    g_app.fd = -1;
    code = app_options(&g_app, argc, argv, &done);
    if (done) {
        return code;
    }
    if (g_app.o.cap.path != NULL) {
        return capture_main(&g_app);
    }
    return capture_options_misplaced(&g_app) ? EXIT_USAGE : EXIT_OK;
}

static void test_capture_refuses_model_options(void **state)
{
    static const char *const extra[][3] = {
        {"-S", "x.scn", NULL}, {"-n", "5", NULL}, {"--drop", "0.1", NULL}, {"-T", "1", NULL},
        {"--max-miss", "3", NULL}, {"--axes", "2", NULL}, {"--csv", "x.csv", NULL}, {"--hold", NULL, NULL}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof extra / sizeof extra[0]; i++) {
        const char *args[] = {"c4g-sim", "--capture", MODE0, "-p", "9", extra[i][0], extra[i][1], NULL};
        assert_int_equal(sim_main(args), EXIT_USAGE);
        assert_null(g_app.cap); /* freed */
    }
}

static void test_capture_options_need_capture(void **state)
{
    static const char *const opt[][3] = {{"--speed", "2", NULL},     {"--topspeed", NULL, NULL},
                                         {"--loop", "2", NULL},      {"--session", "1", NULL},
                                         {"--spin-us", "100", NULL}, {"--replay-live", NULL, NULL},
                                         {"--capture-ports", "1000", NULL}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof opt / sizeof opt[0]; i++) {
        const char *args[] = {"c4g-sim", "-p", "9", opt[i][0], opt[i][1], NULL};
        assert_int_equal(sim_main(args), EXIT_USAGE);
    }
}

static void test_capture_refusals(void **state)
{
    static const char *const session[] = {"c4g-sim", "--capture", MODE0, "-p", "9", "--session", "2", NULL};
    static const char *const missing[] = {"c4g-sim", "--capture", FIXTURES_DIR "/nothere.pcap", "-p", "9", NULL};
    static const char *const both[] = {"c4g-sim", "--capture", MODE0, "--speed", "2", "--topspeed", NULL};
    static const char *const stdin_[] = {"c4g-sim", "--capture", "-", NULL};
    static const char *const host[] = {"c4g-sim", "--capture", MODE0, "-s", "no.such.host.invalid", NULL};
    (void)state;
    assert_int_equal(sim_main(session), EXIT_USAGE); /* the file has 1 session */
    assert_int_equal(sim_main(missing), EXIT_USAGE);
    assert_int_equal(sim_main(both), EXIT_USAGE);
    assert_int_equal(sim_main(stdin_), EXIT_USAGE);
    assert_int_equal(sim_main(host), EXIT_USAGE);
}

/* ---- a played capture on real sockets ---------------------------------------- */

typedef struct silent_pc {
    int fd;                /* the PC server: receives, never answers */
    unsigned long got;     /* datagrams it received */
    int foreign_sent;
} silent_pc_t;

static int udp_bound(uint16_t *port)
{
    struct sockaddr_in a;
    socklen_t l = sizeof a;
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    assert_true(fd >= 0);
    assert_int_equal(bind(fd, (struct sockaddr *)&a, sizeof a), 0);
    assert_int_equal(getsockname(fd, (struct sockaddr *)&a, &l), 0);
    *port = ntohs(a.sin_port);
    return fd;
}

/* Counts the datagrams until 1 s of silence; at the first one, two datagrams from another
 * socket go to the controller's address: c4g-sim must count them foreign. */
static void *silent_pc_run(void *arg)
{
    silent_pc_t *pc = arg;
    uint8_t buf[2048];
    struct pollfd p;
    p.fd = pc->fd;
    p.events = POLLIN;
    while (poll(&p, 1, 1000) > 0) {
        struct sockaddr_in from;
        socklen_t fl = sizeof from;
        if (recvfrom(pc->fd, buf, sizeof buf, 0, (struct sockaddr *)&from, &fl) < 0) {
            break;
        }
        if (pc->got++ == 0U) {
            uint16_t port;
            const int f = udp_bound(&port);
            int k;
            for (k = 0; k < 2; k++) {
                pc->foreign_sent += sendto(f, "x", 1U, 0, (struct sockaddr *)&from, fl) == 1;
            }
            close(f);
        }
    }
    return NULL;
}

static json_int_t jint(json_t *o, const char *a, const char *b)
{
    json_t *v = json_object_get(o, a);
    if (b != NULL) {
        v = json_object_get(v, b);
    }
    assert_true(json_is_integer(v));
    return json_integer_value(v);
}

static void test_capture_stops_at_a_silent_server(void **state)
{
    silent_pc_t pc;
    pthread_t th;
    uint16_t port;
    char port_text[8], out_path[] = "/tmp/test_sim_capture_XXXXXX";
    const char *args[] = {"c4g-sim", "--capture", MODE0, "--bind", "127.0.0.1", "-p", port_text,
                          "--topspeed", "--json", NULL};
    json_t *j;
    json_error_t je;
    int out, saved, rc;
    (void)state;
    memset(&pc, 0, sizeof pc);
    pc.fd = udp_bound(&port);
    (void)snprintf(port_text, sizeof port_text, "%u", (unsigned)port);
    assert_int_equal(pthread_create(&th, NULL, silent_pc_run, &pc), 0);
    out = mkstemp(out_path);
    assert_true(out >= 0);
    (void)fflush(stdout);
    saved = dup(1);
    assert_int_equal(dup2(out, 1), 1);
    rc = sim_main(args);
    (void)fflush(stdout);
    assert_int_equal(dup2(saved, 1), 1);
    close(saved);
    close(out);
    assert_int_equal(pthread_join(th, NULL), 0);
    close(pc.fd);
    j = json_load_file(out_path, 0, &je);
    (void)unlink(out_path);
    assert_non_null(j);
    /* nothing came back from the PC's address: the player stops after CAP_DEAD_PACKETS */
    assert_int_equal(rc, EXIT_NO_ANSWER);
    assert_string_equal(json_string_value(json_object_get(j, "tool")), "c4g-sim");
    assert_string_equal(json_string_value(json_object_get(j, "command")), "capture");
    assert_string_equal(json_string_value(json_object_get(j, "result")), "no-answer");
    /* the session's first controller packets, with their recorded bytes, to the PC's address */
    assert_int_equal(jint(j, "packets", "sent"), CAP_DEAD_PACKETS);
    assert_int_equal(jint(j, "packets", "cyclic"), 0);
    assert_int_equal(jint(j, "passes_done", NULL), 0);
    assert_int_equal(pc.got, CAP_DEAD_PACKETS);
    /* each was judged before the stop; a host that stalls the player turns missing into unjudged */
    assert_int_equal(jint(j, "replies", "missing") + jint(j, "replies", "unjudged"), CAP_DEAD_PACKETS);
    assert_int_equal(jint(j, "replies", "ok"), 0);
    /* c4g-sim's filter: datagrams from another address are counted, never judged, and are
     * not an answer */
    assert_int_equal(pc.foreign_sent, 2);
    assert_int_equal(jint(j, "replies", "foreign"), 2);
    assert_int_equal(jint(j, "replies", "wrong_num"), 0);
    assert_int_equal(jint(j, "divergences", "compared"), 0);
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_capture_refuses_model_options),
        cmocka_unit_test(test_capture_options_need_capture),
        cmocka_unit_test(test_capture_refusals),
        cmocka_unit_test(test_capture_stops_at_a_silent_server),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
