/* cli_progress.h — the progress of long work (render, converge) on stderr:
 * on a terminal a bar redrawn in place with the elapsed time, the rate and
 * the time left (ETA); otherwise (a log file, a Slurm job, GNU parallel) a
 * plain line at every further 10 % of the work or every 10 seconds,
 * whichever comes first, and one when it is done. --quiet: nothing. */
#ifndef ST_CLI_PROGRESS_H
#define ST_CLI_PROGRESS_H

typedef struct st_cli_progress_state {
    const char *label;
    int tty, quiet;
    double work;      /* units of work in all (0: no rate shown) */
    const char *unit; /* what work counts ("samples") */
    double start, last_time, last_fraction; /* monotonic seconds; the last plain line */
} st_cli_progress_state;

/* Starts the clock. quiet (--quiet): st_cli_progress shows nothing. */
void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet);
/* The work in all and its unit, for the rate ("1.20 M samples/s"). */
void st_cli_progress_work(st_cli_progress_state *p, double work, const char *unit);
/* The renderer's progress callback: ctx is an st_cli_progress_state. */
void st_cli_progress(void *ctx, double fraction);

#endif
