/* cli_progress.h — the progress bar of long work (render, converge): drawn
 * on stderr only when it is a terminal, erased when the work is done. */
#ifndef ST_CLI_PROGRESS_H
#define ST_CLI_PROGRESS_H

typedef struct st_cli_progress_state {
    const char *label;
    int tty;
} st_cli_progress_state;

/* quiet (--quiet) or a stderr that is no terminal: st_cli_progress draws nothing. */
void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet);
/* The renderer's progress callback: ctx is an st_cli_progress_state. */
void st_cli_progress(void *ctx, double fraction);

#endif
