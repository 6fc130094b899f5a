/* SPDX-License-Identifier: MIT */
/* c4g-server's wait: it sleeps until the next datagram or the core's next deadline, never
 * on a fixed timer; a signal ends a wait that has no deadline; a controller that stops is
 * found lost at the loss timeout, not later. Real processes and real sockets on 127.0.0.1. */
/* main.c is included (its main renamed) to run the whole server in a child process: its
 * wait and signal handling are static. It comes first: it sets _GNU_SOURCE for ppoll. */
#define main c4g_server_main
#include "../../tools/c4g-server/main.c"
#undef main

#define TH_FIG10_1
#include "test_helpers.h"

#include <fcntl.h>
#include <sys/wait.h>

static unsigned test_port(unsigned k)
{
    return 20000U + ((unsigned)getpid() * 7U + k * 101U) % 20000U;
}

/* The server in a child process on @p argv. */
static pid_t spawn_server(char **argv, int argc)
{
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int devnull = open("/dev/null", O_WRONLY);
        if (devnull >= 0) {
            (void)dup2(devnull, 1);
            (void)dup2(devnull, 2);
        }
        _exit(c4g_server_main(argc, argv));
    }
    return pid;
}

/* voluntary_ctxt_switches of the child's main thread: its wake-ups from a blocking wait */
static long wakeups(pid_t pid)
{
    char path[64], line[128];
    long v = -1;
    FILE *f;
    (void)snprintf(path, sizeof path, "/proc/%d/task/%d/status", (int)pid, (int)pid);
    f = fopen(path, "r");
    if (f == NULL) {
        return -1;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        if (sscanf(line, "voluntary_ctxt_switches: %ld", &v) == 1) {
            break;
        }
    }
    fclose(f);
    return v;
}

static void sleep_ms(unsigned ms)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(ms / 1000U);
    ts.tv_nsec = (long)(ms % 1000U) * 1000000L;
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

/* Exit status of @p pid within @p ms, or -1 (the child is then killed). */
static int wait_exit(pid_t pid, unsigned ms)
{
    int status = 0;
    unsigned t;
    for (t = 0U; t < ms; t += 5U) {
        if (waitpid(pid, &status, WNOHANG) == pid) {
            return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
        }
        sleep_ms(5U);
    }
    kill(pid, SIGKILL);
    (void)waitpid(pid, &status, 0);
    return -1;
}

/* One packet of a start-up and cyclic sequence (NUM @p num: zeros, the figure 10.1 init
 * packet at 10, mode-0 cyclic packets from 13) to @p to, and its reply read. Returns the
 * time just before the send (the server receives the packet after it). */
static uint64_t send_tick(int fd, const struct sockaddr_in *to, int num)
{
    uint64_t t_sent;
    uint8_t b[C4G_INIT_SIZE], r[1400];
    size_t len;
    if (num == 10) {
        memcpy(b, th_fig, sizeof th_fig);
        th_put_u32(b, (uint32_t)num);
        len = sizeof th_fig;
    } else if (num < 13) {
        memset(b, 0, sizeof b);
        th_put_u32(b, (uint32_t)num);
        len = C4G_CYCLIC_SIZE(6U);
    } else {
        len = th_ctrl_bytes(b, sizeof b, num, 6U, C4G_MODE_0);
    }
    t_sent = now_ns();
    assert_int_equal(sendto(fd, b, len, 0, (const struct sockaddr *)to, sizeof *to), (ssize_t)len);
    assert_true(recv(fd, r, sizeof r, 0) > 0); /* every packet of the start-up is answered */
    return t_sent;
}

/* A client socket for the server on @p port (replies within 1 s) and its address. */
static int client(const char *port, struct sockaddr_in *to)
{
    struct timeval tv = {1, 0};
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    assert_true(fd >= 0);
    (void)setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    memset(to, 0, sizeof *to);
    to->sin_family = AF_INET;
    to->sin_port = htons((uint16_t)atoi(port));
    to->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return fd;
}

/* Waiting for a first controller with no deadline at all: the server does not wake (the old
 * 1 ms receive timeout woke it about 1000 times a second), and SIGTERM still ends the wait
 * at once with exit code 0 (a service stopped: docs/cli.md). */
static void test_idle_server_sleeps(void **state)
{
    char port[16];
    char *argv[] = {"c4g-server", "-p", port, "--controller", "127.0.0.1", "-q", NULL};
    pid_t pid;
    long w0, w1;
    (void)state;
    (void)snprintf(port, sizeof port, "%u", test_port(1U));
    pid = spawn_server(argv, 6);
    sleep_ms(300U);
    w0 = wakeups(pid);
    sleep_ms(1000U);
    w1 = wakeups(pid);
    assert_true(w0 >= 0 && w1 >= 0);
    print_message("idle server: %ld wake-ups in 1 s\n", w1 - w0);
    assert_true(w1 - w0 < 20);
    assert_int_equal(kill(pid, SIGTERM), 0);
    assert_int_equal(wait_exit(pid, 1000U), 0);
}

/* A controller that goes quiet in the cyclic phase: the server wakes at the loss deadline
 * (--lost-timeout-ms 150) and exits with code 3, not before and not long after (well under
 * its 5 s idle timeout). */
static void test_loss_at_deadline(void **state)
{
    char port[16];
    char *argv[] = {"c4g-server", "-p", port, "--controller", "127.0.0.1", "-q", "--lost-timeout-ms",
                    "150", "--idle-timeout", "5", NULL};
    struct sockaddr_in to;
    pid_t pid;
    int fd, num, code;
    uint64_t t_last = 0U, t_end;
    (void)state;
    (void)snprintf(port, sizeof port, "%u", test_port(2U));
    pid = spawn_server(argv, 10);
    sleep_ms(200U);
    fd = client(port, &to);
    for (num = 1; num <= 40; num++) {
        t_last = send_tick(fd, &to, num);
        sleep_ms(2U);
    }
    code = wait_exit(pid, 2000U);
    t_end = now_ns();
    close(fd);
    print_message("lost after %.1f ms\n", (double)(t_end - t_last) * 1e-6);
    assert_int_equal(code, EXIT_LOST);
    assert_true(t_end - t_last >= 150U * 1000000ULL);
    /* not long after: far below the 5 s idle timeout and any fixed long sleep; the margin
     * over 150 ms absorbs a loaded host (this test also runs under valgrind beside others) */
    assert_true(t_end - t_last < 1000U * 1000000ULL);
}

/* The loop blocks in recvfrom with the deadline timer armed: SIGTERM in the middle of a
 * stream (the timer firing early and being re-armed meanwhile) still ends the run at once
 * with exit code 0 (a service stopped), and every packet before it was answered. */
static void test_signal_under_stream(void **state)
{
    char port[16];
    char *argv[] = {"c4g-server", "-p", port, "--controller", "127.0.0.1", "-q", "--idle-timeout", "5", NULL};
    struct sockaddr_in to;
    pid_t pid;
    int fd, num, code;
    uint64_t t_sig;
    (void)state;
    (void)snprintf(port, sizeof port, "%u", test_port(3U));
    pid = spawn_server(argv, 8);
    sleep_ms(200U);
    fd = client(port, &to);
    for (num = 1; num <= 120; num++) { /* well past the 10-period silence threshold */
        (void)send_tick(fd, &to, num);
        sleep_ms(1U);
    }
    t_sig = now_ns();
    assert_int_equal(kill(pid, SIGTERM), 0);
    code = wait_exit(pid, 2000U);
    print_message("stopped %.1f ms after SIGTERM\n", (double)(now_ns() - t_sig) * 1e-6);
    close(fd);
    assert_int_equal(code, 0); /* SIGTERM: a service stopped (docs/cli.md) */
    assert_true(now_ns() - t_sig < 500U * 1000000ULL);
}

/* A silence shorter than the loss timeout in the middle of a stream: the timer, re-armed
 * early while packets came, wakes the loop at the silence threshold; the session rides the
 * silence out and counts it (JSON summary), and the stream goes on being answered. */
static void test_silence_counted(void **state)
{
    char port[16], json[64], text[4096];
    char *argv[] = {"c4g-server", "-p", port, "--controller", "127.0.0.1", "-q", "--idle-timeout", "5",
                    "--json-out", json, NULL};
    struct sockaddr_in to;
    pid_t pid;
    int fd, num;
    FILE *f;
    size_t n;
    (void)state;
    (void)snprintf(port, sizeof port, "%u", test_port(4U));
    (void)snprintf(json, sizeof json, "/tmp/c4g-wait-%d.json", (int)getpid());
    pid = spawn_server(argv, 10);
    sleep_ms(200U);
    fd = client(port, &to);
    for (num = 1; num <= 80; num++) {
        (void)send_tick(fd, &to, num);
        sleep_ms(num == 50 ? 200U : 1U); /* 200 ms: past 10 periods, short of the 1 s loss */
    }
    assert_int_equal(kill(pid, SIGTERM), 0);
    assert_int_equal(wait_exit(pid, 2000U), 0);
    close(fd);
    f = fopen(json, "r");
    assert_non_null(f);
    n = fread(text, 1U, sizeof text - 1U, f);
    text[n] = '\0';
    fclose(f);
    (void)remove(json);
    /* the 200 ms gap is one silence; a host slow enough (valgrind beside other tests) to
     * leave 10 periods between two of the other packets makes another, as it would for a
     * real controller: at least one, and the number is what the JSON says */
    {
        const char *p = strstr(text, "\"silences\":");
        assert_non_null(p);
        assert_true(atoi(p + strlen("\"silences\":")) >= 1);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_idle_server_sleeps),
        cmocka_unit_test(test_loss_at_deadline),
        cmocka_unit_test(test_signal_under_stream),
        cmocka_unit_test(test_silence_counted),
    };
    return cmocka_run_group_tests(tests, th_load_fig, NULL);
}
