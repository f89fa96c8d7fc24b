/* cli_progress.c — a 40-column bar on stderr, redrawn in place with "\r"
 * (so only on a terminal: a log file would collect every frame). */
#include "cli_progress.h"

#include <stdio.h>
#include <unistd.h>

void st_cli_progress(void *ctx, double fraction)
{
    st_cli_progress_state *p = ctx;
    if (!p->tty)
        return;
    int width = 40, fill = (int)(fraction * width + 0.5);
    fprintf(stderr, "\r%s [", p->label);
    for (int i = 0; i < width; i++)
        fputc(i < fill ? '#' : ' ', stderr);
    fprintf(stderr, "] %3.0f%%", fraction * 100.0);
    if (fraction >= 1.0)
        fputs("\r\033[K", stderr);
    fflush(stderr);
}

void st_cli_progress_init(st_cli_progress_state *p, const char *label, int quiet)
{
    p->label = label;
    p->tty = !quiet && isatty(fileno(stderr));
}
