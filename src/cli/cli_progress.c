/* cli_progress.c — progress on stderr (see cli_progress.h): a 30-column bar
 * redrawn with "\r" on a terminal, plain lines elsewhere (a log would
 * collect every frame of a bar). A ticker thread wakes every second so that
 * a long wave (or a long compilation) still shows the time moving: the bar
 * redrawn, or off a terminal a line once 10 seconds have passed without one. */
#include "cli_progress.h"

#include <errno.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>

#define PLAIN_STEP 0.1     /* a plain line at every further 10 % ... */
#define PLAIN_SECONDS 10.0 /* ... and at least this often */
#define NOTICE_AFTER 1.0   /* the compile notice, once work lasts this long */
#define NOTICE_TEXT "compiling kernels (first run, cached afterwards)..."

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* "12.3 s", "4 min 05 s", "2 h 07 min". */
static void format_seconds(char *buf, size_t size, double s)
{
    if (s < 60.0)
        snprintf(buf, size, "%.1f s", s);
    else if (s < 3600.0)
        snprintf(buf, size, "%d min %02d s", (int)(s / 60.0), (int)s % 60);
    else
        snprintf(buf, size, "%d h %02d min", (int)(s / 3600.0), (int)(s / 60.0) % 60);
}

/* The rate since the first report, or over the whole time when the first
 * report was also the last (the work done in one wave). 0: not known yet. */
static double rate_of(const st_cli_progress_state *p, double fraction, double t)
{
    if (p->work <= 0 || p->reports == 0)
        return 0;
    if (fraction > p->base_fraction && t > p->base_time)
        return p->work * (fraction - p->base_fraction) / (t - p->base_time);
    return fraction >= 1.0 && t > p->start ? p->work / (t - p->start) : 0;
}

/* The seconds left at the pace since the first report; negative: not known. */
static double eta_of(const st_cli_progress_state *p, double fraction, double t)
{
    if (p->reports == 0 || fraction >= 1.0 || fraction <= p->base_fraction ||
        t <= p->base_time)
        return -1.0;
    return (t - p->base_time) * (1.0 - fraction) / (fraction - p->base_fraction);
}

/* "12.3 s elapsed, 1.20 M samples/s, ETA 17.0 s" (no rate without work or
 * before two reports, no ETA before two; rates with k or M from a thousand
 * or a million on: "0.25 renders/s", "8.64 k samples/s"). */
static void format_status(const st_cli_progress_state *p, double fraction, double t, char *buf,
                          size_t size)
{
    char el[32], eta[40] = "", rate[48] = "";
    format_seconds(el, sizeof el, t - p->start);
    double r = rate_of(p, fraction, t), left = eta_of(p, fraction, t);
    if (r >= 1e6)
        snprintf(rate, sizeof rate, ", %.2f M %s/s", r * 1e-6, p->unit);
    else if (r >= 1e3)
        snprintf(rate, sizeof rate, ", %.2f k %s/s", r * 1e-3, p->unit);
    else if (r > 0)
        snprintf(rate, sizeof rate, ", %.3g %s/s", r, p->unit);
    if (left >= 0) {
        char s[32];
        format_seconds(s, sizeof s, left);
        snprintf(eta, sizeof eta, ", ETA %s", s);
    }
    snprintf(buf, size, "%s elapsed%s%s", el, rate, eta);
}

static void draw_bar(const st_cli_progress_state *p, double fraction, const char *status)
{
    int width = 30, fill = (int)(fraction * width + 0.5);
    fprintf(stderr, "\r%s [", p->label);
    for (int i = 0; i < width; i++)
        fputc(i < fill ? '#' : ' ', stderr);
    fprintf(stderr, "] %3.0f%%  %s\033[K", fraction * 100.0, status);
    if (fraction >= 1.0)
        fputs("\r\033[K", stderr);
    fflush(stderr);
}

static void plain_line(st_cli_progress_state *p, double fraction, double t)
{
    char status[160];
    format_status(p, fraction, t, status, sizeof status);
    fprintf(stderr, "strata: %s %3.0f%% (%s)\n", p->label, fraction * 100.0, status);
    fflush(stderr);
    p->last_fraction = fraction;
    p->last_time = t;
}

/* Shows fraction at time t (the lock held): the bar, or a plain line at a
 * further step, after p->interval, or at the end. */
static void show(st_cli_progress_state *p, double fraction, double t)
{
    if (p->tty) {
        char status[160];
        format_status(p, fraction, t, status, sizeof status);
        draw_bar(p, fraction, status);
    } else if (fraction >= 1.0 || fraction >= p->last_fraction + PLAIN_STEP ||
               t >= p->last_time + p->interval) {
        plain_line(p, fraction, t);
    }
}

void st_cli_progress(void *ctx, double fraction)
{
    st_cli_progress_state *p = ctx;
    if (p->quiet)
        return;
    pthread_mutex_lock(&p->lock);
    double t = now();
    if (p->reports++ == 0) {
        p->base_time = t;
        p->base_fraction = fraction;
    }
    p->fraction = fraction;
    show(p, fraction, t);
    pthread_mutex_unlock(&p->lock);
}

/* The notice's tick: the message once the work lasts NOTICE_AFTER, then off a
 * terminal a line every p->interval. */
static void notice_tick(st_cli_progress_state *p, double t)
{
    char el[32];
    if (p->reports == 0 && t >= p->start + NOTICE_AFTER) {
        fprintf(stderr, "strata: " NOTICE_TEXT "\n");
        p->reports = 1;
        p->last_time = t;
    } else if (p->reports && !p->tty && t >= p->last_time + p->interval) {
        format_seconds(el, sizeof el, t - p->start);
        fprintf(stderr, "strata: compiling kernels, %s elapsed\n", el);
        p->last_time = t;
    }
    fflush(stderr);
}

/* The ticker: every second, the bar redrawn with the time moving, or off a
 * terminal a plain line when p->interval passed without one. */
static void *tick(void *arg)
{
    st_cli_progress_state *p = arg;
    pthread_mutex_lock(&p->lock);
    while (!p->stop) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_sec += 1;
        if (pthread_cond_timedwait(&p->wake, &p->lock, &until) != ETIMEDOUT || p->stop)
            continue;
        double t = now();
        if (p->notice)
            notice_tick(p, t);
        else if (p->fraction < 1.0 && (p->tty || t >= p->last_time + p->interval))
            show(p, p->fraction, t);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet)
{
    p->label = label;
    p->quiet = quiet;
    p->tty = !quiet && isatty(fileno(stderr));
    p->work = 0;
    p->unit = "";
    p->start = p->last_time = now();
    p->last_fraction = p->fraction = 0;
    p->base_time = p->base_fraction = 0;
    p->reports = p->notice = p->stop = 0;
    p->interval = PLAIN_SECONDS;
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    p->ticking = !quiet && pthread_create(&p->ticker, NULL, tick, p) == 0;
}

void st_cli_progress_work(st_cli_progress_state *p, double work, const char *unit)
{
    pthread_mutex_lock(&p->lock); /* the ticker may be drawing already */
    p->work = work;
    p->unit = unit;
    pthread_mutex_unlock(&p->lock);
}

void st_cli_progress_done(st_cli_progress_state *p)
{
    pthread_mutex_lock(&p->lock);
    p->stop = 1;
    pthread_cond_signal(&p->wake);
    if (p->tty && !p->notice && p->reports && p->fraction < 1.0) /* a failed render's bar */
        fputs("\r\033[K", stderr);
    pthread_mutex_unlock(&p->lock);
    if (p->ticking)
        pthread_join(p->ticker, NULL);
    p->ticking = 0;
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
}

void st_cli_notice_start(st_cli_notice *n, int quiet)
{
    st_cli_progress_init(&n->p, "compile", 1); /* no ticker yet: set the mode first */
    n->p.quiet = quiet;
    n->p.tty = !quiet && isatty(fileno(stderr));
    n->p.notice = 1;
    n->p.ticking = !quiet && pthread_create(&n->p.ticker, NULL, tick, &n->p) == 0;
}

void st_cli_notice_stop(st_cli_notice *n)
{
    st_cli_progress_done(&n->p);
}
