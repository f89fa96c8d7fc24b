/* cli_progress.h — the progress of long work (render, converge, compare,
 * and the kernel compilation before them) on stderr: on a terminal a bar
 * redrawn in place with the elapsed time, the rate and the time left (ETA);
 * otherwise (a log file, a Slurm job, GNU parallel) a plain line at every
 * further 10 % of the work and at least every 10 seconds, and one when it is
 * done. The rate and the ETA are counted from the first report (the end of
 * the first wave), so set-up before it does not make them wrong. --quiet:
 * nothing. A thread keeps the time moving between reports. */
#ifndef ST_CLI_PROGRESS_H
#define ST_CLI_PROGRESS_H

#include <pthread.h>

typedef struct st_cli_progress_state {
    const char *label;
    int tty, quiet;
    double work;      /* units of work in all (0: no rate shown) */
    const char *unit; /* what work counts ("samples") */
    double start, last_time, last_fraction; /* monotonic seconds; the last plain line */
    double fraction;                        /* the latest report */
    double interval; /* seconds between plain lines at the most (10; tests shorten it) */
    double base_time, base_fraction;        /* the first report: rate and ETA from here */
    int reports;                            /* reports so far */
    int notice;                             /* a st_cli_notice: no fraction, one message */
    /* the ticker thread and what it shares with the reporting thread */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t ticker;
    int ticking, stop;
} st_cli_progress_state;

/* Starts the clock (and, unless quiet, the ticker). quiet (--quiet): nothing
 * is shown. Every init needs its st_cli_progress_done. */
void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet);
/* The work in all and its unit, for the rate ("1.20 M samples/s"). */
void st_cli_progress_work(st_cli_progress_state *p, double work, const char *unit);
/* The renderer's progress callback: ctx is an st_cli_progress_state. */
void st_cli_progress(void *ctx, double fraction);
/* Stops the ticker (a bar left unfinished by a failure is cleared). */
void st_cli_progress_done(st_cli_progress_state *p);

/* The kernel compilation's notice: st_cli_notice_start starts a thread
 * that, if the work has not ended within a second, prints
 * "strata: compiling kernels (first run, cached afterwards)..." and then,
 * off a terminal, a line every 10 seconds while it lasts; st_cli_notice_stop
 * ends it. quiet: nothing. */
typedef struct st_cli_notice {
    st_cli_progress_state p;
} st_cli_notice;
void st_cli_notice_start(st_cli_notice *n, int quiet);
void st_cli_notice_stop(st_cli_notice *n);

#endif
