/* cli_progress.c — progress on stderr (see cli_progress.h): a 30-column bar
 * redrawn with "\r" on a terminal, plain lines elsewhere (a log would
 * collect every frame of a bar). */
#include "cli_progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

#define PLAIN_STEP 0.1     /* a plain line at every further 10 % ... */
#define PLAIN_SECONDS 10.0 /* ... or after this long without one */

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

/* "12.3 s elapsed, 1.20 M samples/s, ETA 17.0 s" (no rate without work, no ETA before any;
 * rates with k or M from a thousand or a million on: "0.25 renders/s", "8.64 k samples/s"). */
static void format_status(const st_cli_progress_state *p, double fraction, double elapsed,
                          char *buf, size_t size)
{
    char el[32], eta[32], rate[48] = "";
    format_seconds(el, sizeof el, elapsed);
    double r = p->work > 0 && elapsed > 0 ? p->work * fraction / elapsed : 0;
    if (r >= 1e6)
        snprintf(rate, sizeof rate, ", %.2f M %s/s", r * 1e-6, p->unit);
    else if (r >= 1e3)
        snprintf(rate, sizeof rate, ", %.2f k %s/s", r * 1e-3, p->unit);
    else if (r > 0)
        snprintf(rate, sizeof rate, ", %.3g %s/s", r, p->unit);
    if (fraction > 0 && fraction < 1)
        format_seconds(eta, sizeof eta, elapsed * (1.0 - fraction) / fraction);
    snprintf(buf, size, "%s elapsed%s%s%s", el, rate, fraction > 0 && fraction < 1 ? ", ETA " : "",
             fraction > 0 && fraction < 1 ? eta : "");
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

void st_cli_progress(void *ctx, double fraction)
{
    st_cli_progress_state *p = ctx;
    if (p->quiet)
        return;
    double t = now(), elapsed = t - p->start;
    char status[160];
    format_status(p, fraction, elapsed, status, sizeof status);
    if (p->tty) {
        draw_bar(p, fraction, status);
        return;
    }
    if (fraction < 1.0 && fraction < p->last_fraction + PLAIN_STEP &&
        t < p->last_time + PLAIN_SECONDS)
        return;
    fprintf(stderr, "strata: %s %3.0f%% (%s)\n", p->label, fraction * 100.0, status);
    fflush(stderr);
    p->last_fraction = fraction;
    p->last_time = t;
}

void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet)
{
    p->label = label;
    p->quiet = quiet;
    p->tty = !quiet && isatty(fileno(stderr));
    p->work = 0;
    p->unit = "";
    p->start = p->last_time = now();
    p->last_fraction = 0;
}

void st_cli_progress_work(st_cli_progress_state *p, double work, const char *unit)
{
    p->work = work;
    p->unit = unit;
}
