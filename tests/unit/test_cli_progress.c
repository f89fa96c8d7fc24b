/* test_cli_progress.c — guards src/cli/cli_progress.c, the progress lines on stderr
 * off a terminal: the rate and the time left are counted from the first
 * report (a first wave that carried set-up work must not slow them), a line
 * comes at least every interval even when no report arrives, and the
 * compile notice appears only when the work lasts. stderr is captured in a
 * file; the interval is shortened from 10 s to keep the test short. Times
 * are real (sleeps), so the checks leave room for a loaded machine: each
 * bound sits between the honest value and the value the previous rules
 * gave. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli_progress.h"

static char captured[8192];

static void sleep_s(double s)
{
    struct timespec t = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&t, NULL);
}

/* Runs f with stderr going to a file, then reads what it wrote. */
static void capture(void (*f)(void))
{
    char path[] = "/tmp/st_progress.XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    fflush(stderr);
    int saved = dup(2);
    dup2(fd, 2);
    f();
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    ssize_t n = pread(fd, captured, sizeof captured - 1, 0);
    captured[n > 0 ? n : 0] = '\0';
    close(fd);
    unlink(path);
}

/* Set-up of 1 s before the first report (10 % of 1000 samples), then 40 %
 * more in 0.4 s: the honest rate is 1000 samples/s and 0.5 s are left. Counted
 * from the start the rate would be 500 / 1.4 = 357 samples/s and the time
 * left 1.4 s. */
static void slow_first_wave(void)
{
    st_cli_progress_state p;
    st_cli_progress_init(&p, "t", 0);
    p.tty = 0;
    st_cli_progress_work(&p, 1000, "samples");
    sleep_s(1.0);
    st_cli_progress(&p, 0.1);
    sleep_s(0.4);
    st_cli_progress(&p, 0.5);
    st_cli_progress_done(&p);
}

static void rate_and_eta_from_the_first_report(void **state)
{
    (void)state;
    capture(slow_first_wave);
    const char *line = strstr(captured, "strata: t  50% (");
    assert_non_null(line);
    double rate = 0, eta = -1;
    const char *r = strstr(line, " elapsed, ");
    assert_non_null(r);
    assert_int_equal(sscanf(r, " elapsed, %lf samples/s, ETA %lf s", &rate, &eta), 2);
    assert_true(rate > 600 && rate < 1100); /* honest 1000 (less when sleeps overrun) */
    assert_true(eta > 0.3 && eta < 0.9);    /* honest 0.5 */
    /* the first report alone gives no rate yet: it has nothing to be counted from */
    const char *first = strstr(captured, "strata: t  10% (");
    assert_non_null(first);
    char text[128];
    snprintf(text, sizeof text, "%.*s", (int)strcspn(first, "\n"), first);
    assert_null(strstr(text, "samples/s"));
    assert_null(strstr(text, "ETA"));
}

/* No report for 2.5 s with an interval of 0.2 s: lines keep coming. */
static void silent_work(void)
{
    st_cli_progress_state p;
    st_cli_progress_init(&p, "t", 0);
    p.tty = 0;
    p.interval = 0.2;
    sleep_s(0.1);
    st_cli_progress(&p, 0.01);
    sleep_s(2.6);
    st_cli_progress_done(&p);
}

static void a_line_at_least_every_interval(void **state)
{
    (void)state;
    capture(silent_work);
    int lines = 0;
    for (const char *s = captured; (s = strstr(s, "strata: t   1% (")); s++)
        lines++;
    /* the report at 0.1 s comes before the interval ends (no line); the ticker
     * wakes every second, so at 1 s and 2 s there are lines though nothing
     * was reported since */
    assert_true(lines >= 2);
}

static void quiet_work(void)
{
    st_cli_progress_state p;
    st_cli_progress_init(&p, "t", 1);
    p.interval = 0.2;
    st_cli_progress(&p, 0.5);
    sleep_s(1.3);
    st_cli_progress(&p, 1.0);
    st_cli_progress_done(&p);
}

static void quiet_shows_nothing(void **state)
{
    (void)state;
    capture(quiet_work);
    assert_string_equal(captured, "");
}

static void short_compile(void)
{
    st_cli_notice n;
    st_cli_notice_start(&n, 0);
    sleep_s(0.2);
    st_cli_notice_stop(&n);
}

static void long_compile(void)
{
    st_cli_notice n;
    st_cli_notice_start(&n, 0);
    sleep_s(2.2);
    st_cli_notice_stop(&n);
}

static void quiet_compile(void)
{
    st_cli_notice n;
    st_cli_notice_start(&n, 1);
    sleep_s(2.2);
    st_cli_notice_stop(&n);
}

static void compile_notice_only_when_it_lasts(void **state)
{
    (void)state;
    capture(short_compile);
    assert_string_equal(captured, "");
    capture(long_compile);
    assert_string_equal(captured, "strata: compiling kernels (first run, cached afterwards)...\n");
    capture(quiet_compile);
    assert_string_equal(captured, "");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rate_and_eta_from_the_first_report),
        cmocka_unit_test(a_line_at_least_every_interval),
        cmocka_unit_test(quiet_shows_nothing),
        cmocka_unit_test(compile_notice_only_when_it_lasts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
