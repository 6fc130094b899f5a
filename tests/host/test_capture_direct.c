/* SPDX-License-Identifier: MIT */
/* The capture reader's direct path (lib/host/c4gh_capture.c: a plain pcap file opened by
 * path is parsed from its own buffer, unusual records handed back to libpcap) against
 * libpcap's path (the same file opened as a stream): every result, message, field and
 * payload byte the same, on every pcap fixture and on damaged copies of one (cut at many
 * offsets, a record longer than the snap length, a time stamp libpcap reads as negative). */
#include "test_helpers.h"
#include <dirent.h>
#include <unistd.h>

#include "c4gh_capture.h"

static void same_reading(const char *path)
{
    char e1[400], e2[400];
    c4gh_cap_t *a = c4gh_cap_open(path, e1, sizeof e1);
    FILE *fp = fopen(path, "rb");
    c4gh_cap_t *b;
    unsigned n = 0U;
    assert_non_null(fp);
    b = c4gh_cap_open_stream(fp, path, e2, sizeof e2);
    if (a == NULL || b == NULL) {
        assert_true(a == NULL && b == NULL);
        assert_string_equal(e1, e2);
        return;
    }
    for (;;) {
        c4gh_cap_pkt_t p, q;
        const c4gh_cap_res_t r1 = c4gh_cap_next(a, &p, e1, sizeof e1);
        const c4gh_cap_res_t r2 = c4gh_cap_next(b, &q, e2, sizeof e2);
        if (r1 != r2) {
            fail_msg("%s: record %u: result %d (direct) against %d (libpcap)", path, n, (int)r1, (int)r2);
        }
        if (r1 == C4GH_CAP_END || r1 == C4GH_CAP_FATAL) {
            if (r1 == C4GH_CAP_FATAL) {
                assert_string_equal(e1, e2);
            }
            break;
        }
        if (r1 == C4GH_CAP_BAD) {
            assert_string_equal(e1, e2);
        } else if (r1 == C4GH_CAP_DATAGRAM) {
            assert_true(p.frame == q.frame && p.offset == q.offset && p.ts_ns == q.ts_ns &&
                        p.src_ip == q.src_ip && p.dst_ip == q.dst_ip && p.src_port == q.src_port &&
                        p.dst_port == q.dst_port && p.len == q.len);
            assert_memory_equal(p.payload, q.payload, p.len);
        }
        n++;
    }
    assert_memory_equal(c4gh_cap_counts(a), c4gh_cap_counts(b), sizeof(c4gh_cap_counts_t));
    c4gh_cap_close(a);
    c4gh_cap_close(b);
}

static void test_fixtures(void **state)
{
    DIR *d = opendir(FIXTURES_DIR "/replay");
    struct dirent *de;
    unsigned files = 0U;
    (void)state;
    assert_non_null(d);
    while ((de = readdir(d)) != NULL) {
        char path[1024];
        const size_t l = strlen(de->d_name);
        if (l < 5U || strcmp(de->d_name + l - 5U, ".pcap") != 0) {
            continue;
        }
        (void)snprintf(path, sizeof path, "%s/replay/%s", FIXTURES_DIR, de->d_name);
        same_reading(path);
        files++;
    }
    closedir(d);
    assert_true(files > 20U);
}

static void write_file(const char *path, const uint8_t *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1U, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static void test_damaged(void **state)
{
    static uint8_t buf[1U << 20];
    char path[] = "/tmp/c4g-test-capture-XXXXXX";
    const int fd = mkstemp(path);
    const size_t n = th_read_file(FIXTURES_DIR "/replay/mode4.pcap", buf, sizeof buf);
    size_t cut, rec2;
    uint32_t w;
    (void)state;
    assert_true(fd >= 0);
    (void)close(fd);
    assert_true(n > 2000U && n < sizeof buf);
    for (cut = 0U; cut < 2000U; cut += 7U) { /* cut in the headers, records and data */
        write_file(path, buf, cut);
        same_reading(path);
    }
    write_file(path, buf, n - 3U);
    same_reading(path);
    memcpy(&w, buf + 24U + 8U, 4U); /* the first record's caplen */
    rec2 = 24U + 16U + w;
    memcpy(&w, buf + 16U, 4U);      /* the snap length, and a second record over it */
    w += 1U;
    memcpy(buf + rec2 + 8U, &w, 4U);
    write_file(path, buf, n);
    same_reading(path);
    memcpy(&w, buf + 16U, 4U);
    memcpy(buf + rec2 + 8U, &w, 4U);
    w = 0x80000001U;                /* a time stamp libpcap reads as negative */
    memcpy(buf + rec2, &w, 4U);
    write_file(path, buf, n);
    same_reading(path);
    (void)unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixtures),
        cmocka_unit_test(test_damaged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
