/* cli_error.c — the CLI's error line and exit statuses: library code fills
 * an st_error, only these two functions print it (STYLE.md §3). */
#include "cli_error.h"

#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <unistd.h>

#include "st_outfile.h"

/* A C0 control (ESC, BEL, newline...), DEL, or the second byte of a UTF-8 C1
 * control (0xC2 0x80..0x9F, which terminals also obey: CSI is 0xC2 0x9B). */
static int is_control(const unsigned char *p)
{
    return *p < 0x20 || *p == 0x7f || (p[0] == 0xc2 && p[1] >= 0x80 && p[1] <= 0x9f);
}

void st_cli_put_line(const char *prefix, const char *msg)
{
    fputs(prefix, stderr);
    for (const unsigned char *p = (const unsigned char *)msg; *p; p++) {
        if (!is_control(p)) {
            fputc(*p, stderr);
            continue;
        }
        if (p[0] == 0xc2) /* both bytes of a C1 control */
            fprintf(stderr, "\\x%02X", *p++);
        fprintf(stderr, "\\x%02X", *p);
    }
    fputc('\n', stderr);
}

int st_cli_fail(const st_error *err)
{
    st_cli_put_line("strata: error: ", err->msg[0] ? err->msg : st_status_text(err->status));
    return err->status == ST_ERR_USAGE ? ST_CLI_EXIT_USAGE : ST_CLI_EXIT_FAIL;
}

int st_cli_usage_error(const char *fmt, ...)
{
    char msg[1024]; /* a longer message is cut: an option's value is no reason for a page */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    st_cli_put_line("strata: error: ", msg); /* option values quoted are the user's bytes */
    return ST_CLI_EXIT_USAGE;
}

int st_cli_check_apart(const st_outfile_role *files, int n, int nout)
{
    st_error err = {0};
    return st_outfile_check_apart(files, n, nout, &err) == ST_OK ? ST_CLI_OK : st_cli_fail(&err);
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
    /* every signal whose default action ends the process and that may be caught; SIGKILL cannot
     * be, and its temporaries are removed by the next write into their folder */
    static const int ending[] = {SIGHUP,  SIGINT,  SIGQUIT,   SIGTERM, SIGALRM,
                                 SIGUSR1, SIGUSR2, SIGVTALRM, SIGXCPU};
    struct sigaction sa = {0};
    sa.sa_handler = on_interrupt;
    sigfillset(&sa.sa_mask); /* one handler at a time */
    for (size_t i = 0; i < sizeof ending / sizeof ending[0]; i++)
        sigaction(ending[i], &sa, NULL);
    /* a closed pipe or a file-size limit is a failed write (EPIPE, EFBIG), reported by the
     * writer with exit status 1 and its temporaries removed, not a silent death */
    signal(SIGPIPE, SIG_IGN);
    signal(SIGXFSZ, SIG_IGN);
}
