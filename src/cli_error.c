/* cli_error.c — the CLI's error line and exit statuses: library code fills
 * an st_error, only these two functions print it (STYLE.md §3). */
#include "cli_error.h"

#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <unistd.h>

#include "st_outfile.h"

int st_cli_fail(const st_error *err)
{
    fprintf(stderr, "strata: error: %s\n", err->msg[0] ? err->msg : st_status_text(err->status));
    return err->status == ST_ERR_USAGE ? ST_CLI_EXIT_USAGE : ST_CLI_EXIT_FAIL;
}

int st_cli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("strata: error: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return ST_CLI_EXIT_USAGE;
}

/* Whatever thread the signal lands on: remove the temporaries, end at once
 * with the shell's status for the signal (128 + its number). */
static void on_interrupt(int sig)
{
    st_outfile_remove_temporaries();
    _exit(128 + sig);
}

void st_cli_catch_interrupts(void)
{
    struct sigaction sa = {0};
    sa.sa_handler = on_interrupt;
    sigfillset(&sa.sa_mask); /* one handler at a time */
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}
