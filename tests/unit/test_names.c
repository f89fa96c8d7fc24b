/* test_names.c — guards src/base/names.c (include/st_names.h): lookup ignores case; the nearest name
 * follows the rule the header states (a prefix of 3+ bytes, or at most max(2, len/3) edits and
 * fewer than the name's length). Distances here are counted by hand. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "st_names.h"

static const char *const names[] = {"random", "halton", "hammersley", "best-candidate", "sobol"};
#define N 5

static void lookup_ignores_case(void **state)
{
    (void)state;
    assert_int_equal(st_name_lookup(names, N, "halton"), 1);
    assert_int_equal(st_name_lookup(names, N, "HaLtOn"), 1);
    assert_int_equal(st_name_lookup(names, N, "BEST-CANDIDATE"), 3);
    assert_int_equal(st_name_lookup(names, N, "halto"), -1);
    assert_int_equal(st_name_lookup(names, N, ""), -1);
}

static void nearest_follows_the_rule(void **state)
{
    (void)state;
    assert_int_equal(st_name_nearest(names, N, "hallton"), 1);  /* 1 insertion */
    assert_int_equal(st_name_nearest(names, N, "HALTNO"), 1);   /* 2 substitutions */
    assert_int_equal(st_name_nearest(names, N, "sobl"), 4);     /* 1 deletion */
    assert_int_equal(st_name_nearest(names, N, "best"), 3);     /* a prefix */
    assert_int_equal(st_name_nearest(names, N, "hamersly"), 2); /* 2 deletions */
    assert_int_equal(st_name_nearest(names, N, "xyzzy"), -1);   /* 5 or more from each */
    assert_int_equal(st_name_nearest(names, N, "ab"), -1);      /* 2 edits, not < length 2 */
    assert_int_equal(st_name_nearest(names, N, "halxxx"), -1);  /* 3 edits > max(2, 6/3) */
    /* a long name allows len/3 edits: 14 bytes, 4 */
    assert_int_equal(st_name_nearest(names, N, "bxst-cxndxdxte"), 3); /* 4 substitutions, 14/3 */
    assert_int_equal(st_name_nearest(names, N, "bxst-cxndxdxtx"), -1); /* 5 > 14/3 */
}

static void list_joins_and_truncates(void **state)
{
    (void)state;
    char buf[64];
    st_name_list(names, 2, buf, sizeof buf);
    assert_string_equal(buf, "random, halton");
    char small[8];
    st_name_list(names, N, small, sizeof small);
    assert_string_equal(small, "random,");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lookup_ignores_case),
        cmocka_unit_test(nearest_follows_the_rule),
        cmocka_unit_test(list_joins_and_truncates),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
