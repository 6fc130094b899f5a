/* SPDX-License-Identifier: MIT */
/* Capture reader: libpcap for the file formats, our own checks for the link, IPv4 and UDP
 * headers (a capture from the shop floor is evidence: every length is checked against the
 * bytes actually captured before a byte is read). */
#define _GNU_SOURCE /* fopencookie: a pipe read after its first bytes were looked at */
#include "c4gh_capture.h"
#include "c4gopen.h"

#include <errno.h>
#include <pcap/pcap.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdio_ext.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Link types by number, so the reader does not depend on which DLT_ names this libpcap
 * defines (DLT_LINUX_SLL2 is recent). */
enum {
    LT_NULL = 0, LT_EN10MB = 1, LT_RAW_OLD = 12, LT_RAW_BSD = 14, LT_LOOP = 108,
    LT_RAW = 101, LT_SLL = 113, LT_IPV4 = 228, LT_SLL2 = 276
};

#define ETH_IPV4 0x0800U
#define ETH_VLAN 0x8100U
#define ETH_QINQ 0x88A8U
#define ETH_VLAN_OLD 0x9100U
#define IPPROTO_UDP_NUM 17U

struct c4gh_cap {
    pcap_t *pc;
    FILE *fp;          /* libpcap's stream, for byte offsets */
    char path[1024];
    int link;
    int ng;
    int nano;
    uint64_t size;
    uint64_t rec_off;  /* offset of the record being read */
    uint64_t next_off; /* pcap: the next record's, counted (ftell is a system call each) */
    c4gh_cap_counts_t n;
    /* The direct reader of a plain pcap file (see next_record): the records are parsed in
     * place from a 1 MiB buffer instead of libpcap's two freads each. */
    uint8_t *buf;
    size_t blen, bpos;
    int eof;
    uint32_t snaplen;
    long ts_scale;     /* 1000: microsecond time stamps; 1: nanosecond */
    struct pcap_pkthdr hdr;
};

#define DIRECT_BUF ((size_t)1U << 20)
#define DIRECT_MAX_CAPLEN 262144U

static void direct_start(c4gh_cap_t *c);

static uint16_t be16(const uint8_t *p) { return (uint16_t)(((unsigned)p[0] << 8) | p[1]); }
static uint32_t be32(const uint8_t *p)
{
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
}

const char *c4gh_cap_ip_str(uint32_t ip, char buf[16])
{
    (void)snprintf(buf, 16, "%u.%u.%u.%u", (unsigned)(ip >> 24), (unsigned)((ip >> 16) & 255U),
                   (unsigned)((ip >> 8) & 255U), (unsigned)(ip & 255U));
    return buf;
}

static void say(char *err, size_t errlen, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static void say(char *err, size_t errlen, const char *fmt, ...)
{
    va_list ap;
    if (err == NULL || errlen == 0U) {
        return;
    }
    va_start(ap, fmt);
    (void)vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* A clear refusal of what is not a file before libpcap's. */
static int sniff(const char *path, uint64_t *size, char *err, size_t errlen)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        say(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    if (S_ISDIR(st.st_mode)) {
        say(err, errlen, "%s: is a directory, not a capture file", path);
        return -1;
    }
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode) && !S_ISCHR(st.st_mode)) {
        say(err, errlen, "%s: not a regular file, pipe or terminal", path);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        st.st_size = 0; /* a pipe: size unknown */
    }
    *size = (uint64_t)st.st_size;
    return 0;
}

static int known_magic(const uint8_t m[4], int *ng, int *nano)
{
    const uint32_t le = c4g_le_u32(m);
    *ng = 0;
    *nano = 0;
    switch (le) {
    case 0xA1B2C3D4U: case 0xD4C3B2A1U: return 1;
    case 0xA1B23C4DU: case 0x4D3CB2A1U: *nano = 1; return 1;
    case 0x0A0D0D0AU: *ng = 1; return 1;
    default: return 0;
    }
}

static int link_supported(int lt)
{
    switch (lt) {
    case LT_NULL: case LT_EN10MB: case LT_RAW_OLD: case LT_RAW_BSD: case LT_LOOP: case LT_RAW:
    case LT_SLL: case LT_IPV4: case LT_SLL2:
        return 1;
    default:
        return 0;
    }
}

/* The reader over an open stream (libpcap owns it from here on). */
static c4gh_cap_t *open_stream(FILE *fp, const char *name, uint64_t size, char *err, size_t errlen)
{
    char perr[PCAP_ERRBUF_SIZE];
    c4gh_cap_t *c = calloc(1U, sizeof *c);
    if (c == NULL) {
        say(err, errlen, "%s: out of memory", name);
        (void)fclose(fp);
        return NULL;
    }
    perr[0] = '\0';
    c->pc = pcap_fopen_offline_with_tstamp_precision(fp, PCAP_TSTAMP_PRECISION_NANO, perr);
    if (c->pc == NULL) {
        say(err, errlen, "%s: offset 0: cannot read the capture header: %s", name, perr);
        (void)fclose(fp);
        free(c);
        return NULL;
    }
    c->link = pcap_datalink(c->pc);
    if (!link_supported(c->link)) {
        const char *nm = pcap_datalink_val_to_name(c->link);
        say(err, errlen, "%s: link type %d (%s) is not supported (Ethernet, raw IPv4, Linux SLL/SLL2, "
            "BSD loopback)", name, c->link, nm != NULL ? nm : "unknown");
        pcap_close(c->pc);
        free(c);
        return NULL;
    }
    c->fp = fp;
    (void)snprintf(c->path, sizeof c->path, "%s", name);
    c->size = size;
    c->rec_off = (ftell(fp) >= 0) ? (uint64_t)ftell(fp) : 0U;
    c->next_off = c->rec_off;
    return c;
}

/* A stream that cannot seek (a pipe, stdin): its first bytes, read to look at the magic,
 * are given again before the rest, and ftell counts the bytes read. */
typedef struct replay_in {
    FILE *src;
    uint8_t head[4];
    size_t n, pos;
    uint64_t off;
} replay_in_t;

static ssize_t rin_read(void *ck, char *buf, size_t size)
{
    replay_in_t *r = ck;
    size_t k = 0U;
    while (r->pos < r->n && k < size) {
        buf[k++] = (char)r->head[r->pos++];
    }
    if (k < size) {
        k += fread(buf + k, 1U, size - k, r->src);
    }
    r->off += k;
    return (ssize_t)k;
}

static int rin_seek(void *ck, off64_t *offset, int whence)
{
    const replay_in_t *r = ck;
    if (whence != SEEK_CUR || *offset != 0) {
        return -1;
    }
    *offset = (off64_t)r->off;
    return 0;
}

static int rin_close(void *ck)
{
    replay_in_t *r = ck;
    const int rc = fclose(r->src);
    free(r);
    return rc;
}

static FILE *replay_head(FILE *fp, const uint8_t magic[4])
{
    static const cookie_io_functions_t io = {rin_read, NULL, rin_seek, rin_close};
    replay_in_t *r = calloc(1U, sizeof *r);
    FILE *out;
    if (r == NULL) {
        return NULL;
    }
    r->src = fp;
    memcpy(r->head, magic, 4U);
    r->n = 4U;
    out = fopencookie(r, "rb", io);
    if (out == NULL) {
        free(r);
    }
    return out;
}

c4gh_cap_t *c4gh_cap_open_stream(FILE *fp, const char *name, char *err, size_t errlen)
{
    uint8_t magic[4] = {0, 0, 0, 0};
    int ng = 0, nano = 0;
    const size_t got = fread(magic, 1U, 4U, fp);
    c4gh_cap_t *c;
    if (got < 4U) {
        say(err, errlen, got == 0U ? "%s: empty file, not a capture" : "%s: too short for a capture file header",
            name);
        (void)fclose(fp);
        return NULL;
    }
    if (magic[0] == 0x1FU && magic[1] == 0x8BU) {
        say(err, errlen, "%s: a gzip-compressed file: decompress it first (zcat FILE | " "c4g-replay COMMAND -)",
            name);
        (void)fclose(fp);
        return NULL;
    }
    if (!known_magic(magic, &ng, &nano)) {
        say(err, errlen, "%s: not a pcap or pcapng file (starts with %02x %02x %02x %02x)", name, magic[0],
            magic[1], magic[2], magic[3]);
        (void)fclose(fp);
        return NULL;
    }
    if (fseek(fp, 0L, SEEK_SET) != 0) {
        FILE *again = replay_head(fp, magic); /* a pipe */
        if (again == NULL) {
            say(err, errlen, "%s: cannot read on: %s", name, strerror(errno));
            (void)fclose(fp);
            return NULL;
        }
        fp = again;
    }
    c = open_stream(fp, name, 0U, err, errlen);
    if (c != NULL) {
        c->ng = ng;
        c->nano = nano;
    }
    return c;
}

/* pcapng: the first interface's time stamp resolution (if_tsresol, option 9 of its IDB):
 * 1 if finer than a microsecond. libpcap scales the times but does not say. */
static int pcapng_nano(const char *path)
{
    uint8_t b[512];
    FILE *fp = fopen(path, "rb");
    size_t n, off, end;
    uint32_t shb_len, idb_len;
    int be, nano = 0;
    if (fp == NULL) {
        return 0;
    }
    n = fread(b, 1U, sizeof b, fp);
    (void)fclose(fp);
    if (n < 28U) {
        return 0;
    }
    be = (b[8] == 0x1AU); /* byte-order magic 0x1A2B3C4D as written */
#define RD32(p) (be ? ((uint32_t)(p)[0] << 24 | (uint32_t)(p)[1] << 16 | (uint32_t)(p)[2] << 8 | (p)[3]) \
                    : ((uint32_t)(p)[3] << 24 | (uint32_t)(p)[2] << 16 | (uint32_t)(p)[1] << 8 | (p)[0]))
#define RD16(p) (be ? (uint32_t)((p)[0] << 8 | (p)[1]) : (uint32_t)((p)[1] << 8 | (p)[0]))
    shb_len = RD32(b + 4);
    if (shb_len < 28U || shb_len > n - 20U || RD32(b + shb_len) != 1U) {
        return 0;
    }
    idb_len = RD32(b + shb_len + 4U);
    if (idb_len < 20U || idb_len > n - shb_len) {
        return 0;
    }
    end = shb_len + idb_len - 4U;
    for (off = shb_len + 16U; off + 4U <= end;) {
        const uint32_t code = RD16(b + off), len = RD16(b + off + 2U);
        if (code == 0U || off + 4U + len > end) {
            break;
        }
        if (code == 9U && len >= 1U) {
            const uint8_t r = b[off + 4U];
            nano = (r & 0x80U) ? ((r & 0x7FU) > 20U) : (r > 6U);
        }
        off += 4U + ((len + 3U) & ~3U);
    }
#undef RD32
#undef RD16
    return nano;
}

c4gh_cap_t *c4gh_cap_open(const char *path, char *err, size_t errlen)
{
    uint64_t size = 0U;
    FILE *fp;
    c4gh_cap_t *c;
    if (strcmp(path, "-") == 0) {
        return c4gh_cap_open_stream(stdin, path, err, errlen); /* tcpdump -w - | c4g-replay ... - */
    }
    if (sniff(path, &size, err, errlen) != 0) {
        return NULL;
    }
    fp = fopen(path, "rb");
    if (fp == NULL) {
        say(err, errlen, "%s: %s", path, strerror(errno));
        return NULL;
    }
    /* libpcap reads each record with two small freads: one reader, so no stream locks */
    (void)__fsetlocking(fp, FSETLOCKING_BYCALLER);
    c = c4gh_cap_open_stream(fp, path, err, errlen);
    if (c != NULL) {
        c->size = size;
        if (c->ng) {
            c->nano = pcapng_nano(path);
        } else {
            direct_start(c);
        }
    }
    return c;
}

/* Link header -> offset of the IPv4 header, or a reason to skip (0 = IPv4 at *ip_off). */
typedef enum { L_IPV4 = 0, L_OTHER, L_SHORT } link_res_t;

static link_res_t link_ipv4(const c4gh_cap_t *c, const uint8_t *d, uint32_t caplen, uint32_t *ip_off)
{
    uint32_t off;
    uint16_t et;
    unsigned tags = 0U;
    switch (c->link) {
    case LT_EN10MB:
        if (caplen < 14U) {
            return L_SHORT;
        }
        off = 12U;
        et = be16(d + off);
        while ((et == ETH_VLAN || et == ETH_QINQ || et == ETH_VLAN_OLD) && tags < 4U) {
            off += 4U;
            tags++;
            if (caplen < off + 2U) {
                return L_SHORT;
            }
            et = be16(d + off);
        }
        *ip_off = off + 2U;
        return (et == ETH_IPV4) ? L_IPV4 : L_OTHER;
    case LT_SLL:
        if (caplen < 16U) {
            return L_SHORT;
        }
        *ip_off = 16U;
        return (be16(d + 14) == ETH_IPV4) ? L_IPV4 : L_OTHER;
    case LT_SLL2:
        if (caplen < 20U) {
            return L_SHORT;
        }
        *ip_off = 20U;
        return (be16(d) == ETH_IPV4) ? L_IPV4 : L_OTHER;
    case LT_NULL:
    case LT_LOOP: {
        uint32_t af;
        if (caplen < 4U) {
            return L_SHORT;
        }
        /* the capturing host's byte order (NULL) or network order (LOOP): AF_INET is 2
         * everywhere, so either order of the value 2 is IPv4 */
        af = be32(d);
        *ip_off = 4U;
        return (af == 2U || af == 0x02000000U) ? L_IPV4 : L_OTHER;
    }
    default: /* raw IP */
        *ip_off = 0U;
        if (caplen < 1U) {
            return L_SHORT;
        }
        return ((d[0] >> 4) == 4U) ? L_IPV4 : L_OTHER;
    }
}

static c4gh_cap_res_t bad(c4gh_cap_t *c, char *err, size_t errlen, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static c4gh_cap_res_t bad(c4gh_cap_t *c, char *err, size_t errlen, const char *fmt, ...)
{
    char why[256];
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    c->n.bad++;
    say(err, errlen, "%s: packet %llu (offset %llu): %s", c->path, (unsigned long long)c->n.frames,
        (unsigned long long)c->rec_off, why);
    return C4GH_CAP_BAD;
}

/* The IPv4 and UDP headers of one frame. */
static c4gh_cap_res_t parse_ip(c4gh_cap_t *c, const struct pcap_pkthdr *h, const uint8_t *d, uint32_t ipo,
                          c4gh_cap_pkt_t *p, char *err, size_t errlen)
{
    const uint32_t avail = h->caplen - ipo;     /* captured bytes from the IP header on */
    const uint32_t wire = (h->len > ipo) ? h->len - ipo : 0U; /* bytes on the wire */
    const uint8_t *ip = d + ipo;
    uint32_t ihl, tot, frag, ulen;
    if (avail < 20U) {
        if (wire >= 20U) {
            c->n.cut++;
            return bad(c, err, errlen, "snapshot length cut the IPv4 header (%u of %u bytes captured)",
                       (unsigned)avail, (unsigned)wire);
        }
        return bad(c, err, errlen, "IPv4 header truncated: %u bytes", (unsigned)avail);
    }
    ihl = (uint32_t)(ip[0] & 15U) * 4U;
    tot = be16(ip + 2);
    if ((ip[0] >> 4) != 4U || ihl < 20U) {
        return bad(c, err, errlen, "bad IPv4 header: version %u, header length %u", (unsigned)(ip[0] >> 4),
                   (unsigned)ihl);
    }
    if (tot < ihl) {
        return bad(c, err, errlen, "IPv4 total length %u is below its header length %u", (unsigned)tot,
                   (unsigned)ihl);
    }
    if (tot > wire) {
        return bad(c, err, errlen, "IPv4 total length %u exceeds the frame (%u bytes after the link header)",
                   (unsigned)tot, (unsigned)wire);
    }
    if (ip[9] != IPPROTO_UDP_NUM) {
        c->n.ignored++;
        return C4GH_CAP_IGNORED;
    }
    frag = be16(ip + 6);
    if ((frag & 0x3FFFU) != 0U) {
        c->n.fragments++;
        return bad(c, err, errlen, "IPv4 fragment (id 0x%04x, offset %u, %s): fragments are not "
                   "reassembled", (unsigned)be16(ip + 4), (unsigned)((frag & 0x1FFFU) * 8U),
                   (frag & 0x2000U) != 0U ? "more follow" : "last");
    }
    if (tot > avail) {
        c->n.cut++;
        return bad(c, err, errlen, "snapshot length cut the datagram: %u of %u IP bytes captured",
                   (unsigned)avail, (unsigned)tot);
    }
    if (tot < ihl + 8U) {
        return bad(c, err, errlen, "UDP header truncated: IPv4 total length %u", (unsigned)tot);
    }
    ulen = be16(ip + ihl + 4U);
    if (ulen < 8U || ulen > tot - ihl) {
        return bad(c, err, errlen, "UDP length %u does not fit the IPv4 payload of %u bytes",
                   (unsigned)ulen, (unsigned)(tot - ihl));
    }
    p->src_ip = be32(ip + 12);
    p->dst_ip = be32(ip + 16);
    p->src_port = be16(ip + ihl);
    p->dst_port = be16(ip + ihl + 2U);
    p->payload = ip + ihl + 8U;
    p->len = (size_t)ulen - 8U;
    c->n.udp++;
    return C4GH_CAP_DATAGRAM;
}

/* The direct reader: for a plain pcap file of version 2.4 in the host's byte order, with a
 * link type whose bytes libpcap hands over as they are, read from a path (seekable). It
 * gives what pcap_next_ex gives for every ordinary record; anything else (a record longer
 * than the snap length, a length over the frame's, a truncated record at the end) goes
 * back to libpcap at that record's offset, which then reads on and words the error as it
 * always did: libpcap keeps no read-ahead of its own for these files. */
static void direct_start(c4gh_cap_t *c)
{
    const int lt = c->link;
    if (c->ng || pcap_is_swapped(c->pc) || pcap_major_version(c->pc) != 2 || pcap_minor_version(c->pc) != 4 ||
        !(lt == LT_EN10MB || lt == LT_RAW || lt == LT_RAW_OLD || lt == LT_RAW_BSD || lt == LT_SLL ||
          lt == LT_SLL2 || lt == LT_IPV4) ||
        pcap_snapshot(c->pc) <= 0 || (uint32_t)pcap_snapshot(c->pc) > DIRECT_MAX_CAPLEN) {
        return;
    }
    c->buf = malloc(DIRECT_BUF);
    if (c->buf == NULL) {
        return;
    }
    c->snaplen = (uint32_t)pcap_snapshot(c->pc);
    c->ts_scale = c->nano ? 1L : 1000L;
    c->blen = 0U;
    c->bpos = 0U;
    c->eof = 0;
}

/* At least @p need bytes from bpos on in the buffer, unless the file ends first. */
static size_t direct_fill(c4gh_cap_t *c, size_t need)
{
    size_t have = c->blen - c->bpos;
    if (have < need && !c->eof) {
        memmove(c->buf, c->buf + c->bpos, have);
        c->bpos = 0U;
        c->blen = have;
        while (c->blen < need && !c->eof) {
            const size_t got = fread(c->buf + c->blen, 1U, DIRECT_BUF - c->blen, c->fp);
            c->blen += got;
            if (got == 0U) {
                c->eof = 1;
            }
        }
        have = c->blen;
    }
    return have;
}

/* Back to libpcap from the record at rec_off on. */
static void direct_stop(c4gh_cap_t *c)
{
    free(c->buf);
    c->buf = NULL;
    if (fseek(c->fp, (long)c->rec_off, SEEK_SET) != 0) {
        c->rec_off = c->next_off; /* (a regular file: does not happen) */
    }
}

/* pcap_next_ex's contract: 1 a record, PCAP_ERROR_BREAK at the end, else an error. */
static int next_record(c4gh_cap_t *c, struct pcap_pkthdr **h, const u_char **d)
{
    if (c->buf != NULL) {
        const size_t have = direct_fill(c, 16U);
        if (have == 0U) {
            return PCAP_ERROR_BREAK;
        }
        if (have >= 16U) {
            const uint8_t *r = c->buf + c->bpos;
            uint32_t w[4];
            memcpy(w, r, sizeof w); /* the host's byte order (pcap_is_swapped is 0) */
            /* time stamps libpcap would read as negative or out of range go to it too */
            if (w[0] <= 0x7FFFFFFFU && w[1] < (uint32_t)(1000000000L / c->ts_scale) && w[2] <= c->snaplen &&
                w[2] <= w[3] && direct_fill(c, 16U + (size_t)w[2]) >= 16U + (size_t)w[2]) {
                r = c->buf + c->bpos; /* (the fill may have moved it) */
                c->hdr.ts.tv_sec = (time_t)w[0];
                c->hdr.ts.tv_usec = (suseconds_t)((long)w[1] * c->ts_scale);
                c->hdr.caplen = w[2];
                c->hdr.len = w[3];
                *h = &c->hdr;
                *d = r + 16;
                c->bpos += 16U + (size_t)w[2];
                return 1;
            }
        }
        direct_stop(c);
    }
    return pcap_next_ex(c->pc, h, d);
}

c4gh_cap_res_t c4gh_cap_next(c4gh_cap_t *c, c4gh_cap_pkt_t *p, char *err, size_t errlen)
{
    struct pcap_pkthdr *h = NULL;
    const u_char *d = NULL;
    uint32_t ipo = 0U;
    link_res_t lr;
    int rc;
    if (!c->ng) {
        c->rec_off = c->next_off;
    } else if (c->fp != NULL) {
        const long pos = ftell(c->fp);
        if (pos >= 0) {
            c->rec_off = (uint64_t)pos;
        }
    }
    rc = next_record(c, &h, &d);
    if (rc == PCAP_ERROR_BREAK) {
        return C4GH_CAP_END;
    }
    if (rc != 1) {
        say(err, errlen, "%s: packet %llu (offset %llu): %s", c->path,
            (unsigned long long)c->n.frames + 1U, (unsigned long long)c->rec_off, pcap_geterr(c->pc));
        return C4GH_CAP_FATAL;
    }
    c->n.frames++;
    c->next_off = c->rec_off + 16U + h->caplen; /* a pcap record: 16-byte header, data */
    memset(p, 0, sizeof *p);
    p->frame = c->n.frames;
    p->offset = c->rec_off;
    if (h->ts.tv_sec < 0 || (uint64_t)h->ts.tv_sec > 9000000000ULL || h->ts.tv_usec < 0 ||
        h->ts.tv_usec >= 1000000000L) {
        return bad(c, err, errlen, "timestamp %lld.%09ld s is out of range", (long long)h->ts.tv_sec,
                   (long)h->ts.tv_usec);
    }
    p->ts_ns = (int64_t)h->ts.tv_sec * 1000000000LL + (int64_t)h->ts.tv_usec;
    if (h->caplen > h->len) {
        return bad(c, err, errlen, "captured length %u exceeds the frame length %u",
                   (unsigned)h->caplen, (unsigned)h->len);
    }
    lr = link_ipv4(c, d, h->caplen, &ipo);
    if (lr == L_SHORT) {
        return bad(c, err, errlen, "frame of %u bytes is shorter than its %s header", (unsigned)h->caplen,
                   c4gh_cap_link_name(c));
    }
    if (lr == L_OTHER) {
        c->n.ignored++;
        return C4GH_CAP_IGNORED;
    }
    if (ipo > h->caplen) {
        return bad(c, err, errlen, "frame of %u bytes is shorter than its link header", (unsigned)h->caplen);
    }
    return parse_ip(c, h, d, ipo, p, err, errlen);
}

const c4gh_cap_counts_t *c4gh_cap_counts(const c4gh_cap_t *c) { return &c->n; }

uint64_t c4gh_cap_pos(const c4gh_cap_t *c)
{
    if (c->buf != NULL) {
        return c->next_off; /* the stream is up to 1 MiB ahead */
    }
    if (c->fp != NULL) {
        const long pos = ftell(c->fp);
        if (pos >= 0) {
            return (uint64_t)pos;
        }
    }
    return c->rec_off;
}

uint64_t c4gh_cap_size(const c4gh_cap_t *c) { return c->size; }
const char *c4gh_cap_format(const c4gh_cap_t *c) { return c->ng ? "pcapng" : "pcap"; }
int c4gh_cap_nanosecond(const c4gh_cap_t *c) { return c->nano; }
const char *c4gh_cap_path(const c4gh_cap_t *c) { return c->path; }

const char *c4gh_cap_link_name(const c4gh_cap_t *c)
{
    switch (c->link) {
    case LT_NULL: return "NULL";
    case LT_LOOP: return "LOOP";
    case LT_EN10MB: return "EN10MB";
    case LT_SLL: return "LINUX_SLL";
    case LT_SLL2: return "LINUX_SLL2";
    case LT_IPV4: return "IPV4";
    default: return "RAW";
    }
}

void c4gh_cap_close(c4gh_cap_t *c)
{
    if (c != NULL) {
        pcap_close(c->pc);
        free(c->buf);
        free(c);
    }
}
