/* cli_display.c — the live view in a tev viewer (see cli_display.h). */
#include "cli_display.h"

#include <errno.h>
#include <netdb.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>
#include <fcntl.h>

#include "cli_error.h"

enum { TEV_CREATE_IMAGE = 4, TEV_UPDATE_IMAGE_V3 = 6 };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int st_cli_display_parse(const char *spec, char *host, size_t host_cap, char *port,
                         size_t port_cap)
{
    const char *colon = strrchr(spec, ':');
    const char *h = spec, *h_end = colon;
    if (colon && spec[0] == '[') { /* [IPv6]:PORT */
        h = spec + 1;
        h_end = colon > spec && colon[-1] == ']' ? colon - 1 : NULL;
    }
    char *end;
    errno = 0;
    long p = colon ? strtol(colon + 1, &end, 10) : 0;
    if (!colon || !h_end || h_end <= h || (size_t)(h_end - h) >= host_cap || colon[1] < '0' ||
        colon[1] > '9' || *end || errno || p < 1 || p > 65535)
        return st_cli_usage_error("--display-server %s: expected HOST:PORT (tev listens on "
                                  "localhost:14158 by default)", spec);
    snprintf(host, host_cap, "%.*s", (int)(h_end - h), h);
    snprintf(port, port_cap, "%ld", p);
    return 0;
}

void st_cli_display_init(st_cli_display *d, const char *spec, const char *name, unsigned width,
                         unsigned height)
{
    memset(d, 0, sizeof *d);
    snprintf(d->spec, sizeof d->spec, "%s", spec);
    st_cli_display_parse(spec, d->host, sizeof d->host, d->port, sizeof d->port);
    snprintf(d->name, sizeof d->name, "%s", name);
    d->width = width;
    d->height = height;
    d->fd = -1;
}

static void warn(st_cli_display *d, const char *what)
{
    if (!d->warned)
        fprintf(stderr, "strata: warning: --display-server %s: %s; the render goes on (a "
                "later look tries again)\n", d->spec, what);
    d->warned = 1;
}

/* A TCP connection to host:port within a second, or -1 (errno set). */
static int connect_within(const char *host, const char *port)
{
    struct addrinfo hints = {0}, *list = NULL;
    hints.ai_socktype = SOCK_STREAM;
    if (getaddrinfo(host, port, &hints, &list) != 0) {
        errno = EHOSTUNREACH;
        return -1;
    }
    int fd = -1;
    for (struct addrinfo *a = list; a && fd < 0; a = a->ai_next) {
        fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (fd < 0)
            continue;
        int flags = fcntl(fd, F_GETFL);
        fcntl(fd, F_SETFL, flags | O_NONBLOCK); /* a host that never answers costs a second */
        int rc = connect(fd, a->ai_addr, a->ai_addrlen);
        if (rc < 0 && errno == EINPROGRESS) {
            struct pollfd pf = {fd, POLLOUT, 0};
            int err = ETIMEDOUT;
            socklen_t len = sizeof err;
            if (poll(&pf, 1, 1000) == 1)
                getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
            rc = err ? -1 : 0;
            errno = err;
        }
        fcntl(fd, F_SETFL, flags);
        if (rc < 0) {
            int e = errno;
            close(fd);
            fd = -1;
            errno = e;
        }
    }
    freeaddrinfo(list);
    if (fd >= 0) { /* a viewer that stops reading stalls a send for 2 s at most */
        struct timeval tv = {2, 0};
        setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    }
    return fd;
}

/* A packet under construction: its bytes, little-endian. */
typedef struct packet {
    unsigned char *b;
    size_t n, cap;
    int full; /* out of memory */
} packet;

static void put(packet *p, const void *v, size_t n)
{
    if (p->n + n > p->cap) {
        size_t cap = 2 * (p->n + n);
        unsigned char *b = realloc(p->b, cap);
        if (!b) {
            p->full = 1;
            return;
        }
        p->b = b;
        p->cap = cap;
    }
    memcpy(p->b + p->n, v, n);
    p->n += n;
}

static void put_u32(packet *p, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    put(p, b, 4);
}

static void put_u64(packet *p, uint64_t v)
{
    put_u32(p, (uint32_t)v);
    put_u32(p, (uint32_t)(v >> 32));
}

static void put_f32(packet *p, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put_u32(p, v);
}

static void put_str(packet *p, const char *s) { put(p, s, strlen(s) + 1); }

/* Starts a packet of type t: its length (set by finish), the type, grabFocus. */
static void begin(packet *p, unsigned char t, unsigned char grab_focus)
{
    p->n = 0;
    put_u32(p, 0);
    put(p, &t, 1);
    put(p, &grab_focus, 1);
}

/* Sets the packet's length and sends it all; 0, or -1 with the connection closed. */
static int finish(st_cli_display *d, packet *p)
{
    if (p->full || d->fd < 0)
        return -1;
    uint32_t n = (uint32_t)p->n;
    for (int k = 0; k < 4; k++)
        p->b[k] = (unsigned char)(n >> (8 * k));
    for (size_t sent = 0; sent < p->n;) {
        ssize_t k = send(d->fd, p->b + sent, p->n - sent, MSG_NOSIGNAL);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0) {
            warn(d, k < 0 ? strerror(errno) : "the viewer closed the connection");
            close(d->fd);
            d->fd = -1;
            d->next_try = now() + ST_CLI_DISPLAY_RETRY;
            return -1;
        }
        sent += (size_t)k;
    }
    return 0;
}

static const char *const channels[3] = {"R", "G", "B"};

/* Connects if due, and announces the image (CreateImage) on a new connection. */
static int connect_if_due(st_cli_display *d, packet *p, int final)
{
    if (d->fd >= 0)
        return 0;
    if (!final && now() < d->next_try)
        return -1;
    d->fd = connect_within(d->host, d->port);
    if (d->fd < 0) {
        warn(d, strerror(errno));
        d->next_try = now() + ST_CLI_DISPLAY_RETRY;
        return -1;
    }
    begin(p, TEV_CREATE_IMAGE, 1);
    put_str(p, d->name);
    put_u32(p, d->width);
    put_u32(p, d->height);
    put_u32(p, 3);
    for (int c = 0; c < 3; c++)
        put_str(p, channels[c]);
    return finish(d, p);
}

void st_cli_display_open(st_cli_display *d)
{
    packet p = {0};
    connect_if_due(d, &p, 1);
    free(p.b);
}

void st_cli_display_show(st_cli_display *d, const st_image *img, int final)
{
    packet p = {0};
    if (connect_if_due(d, &p, final) != 0) {
        free(p.b);
        return;
    }
    const unsigned t = ST_CLI_DISPLAY_TILE;
    for (unsigned ty = 0; ty < img->height && d->fd >= 0; ty += t)
        for (unsigned tx = 0; tx < img->width && d->fd >= 0; tx += t) {
            unsigned w = img->width - tx < t ? img->width - tx : t;
            unsigned h = img->height - ty < t ? img->height - ty : t;
            begin(&p, TEV_UPDATE_IMAGE_V3, 0);
            put_str(&p, d->name);
            put_u32(&p, 3);
            for (int c = 0; c < 3; c++)
                put_str(&p, channels[c]);
            put_u32(&p, (uint32_t)(img->x0 + (int32_t)tx));
            put_u32(&p, (uint32_t)(img->y0 + (int32_t)ty));
            put_u32(&p, w);
            put_u32(&p, h);
            for (int c = 0; c < 3; c++) /* interleaved: channel c at c, every 3 floats */
                put_u64(&p, (uint64_t)c);
            for (int c = 0; c < 3; c++)
                put_u64(&p, 3);
            for (unsigned y = 0; y < h; y++)
                for (unsigned x = 0; x < w; x++)
                    for (int c = 0; c < 3; c++)
                        put_f32(&p, img->data[((size_t)(ty + y) * img->width + tx + x) *
                                                  img->channels + (size_t)c]);
            finish(d, &p);
        }
    free(p.b);
}

void st_cli_display_preview(void *ctx, const st_image *so_far)
{
    st_cli_display_show(ctx, so_far, 0);
}

void st_cli_display_close(st_cli_display *d)
{
    if (d->fd >= 0)
        close(d->fd);
    d->fd = -1;
}
