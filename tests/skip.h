/* skip.h — ends a cmocka test as skipped, saying why. cmocka's skip() prints
 * "not ok N # SKIP name" without a reason; ST_SKIP prints the reason on a line
 * "# SKIP why" before it, which tests/run.sh lists (once) at the end of
 * make test. For checks that need what this checkout lacks (../shared's
 * models), never for a check that could run. Include after cmocka.h. */
#ifndef ST_TEST_SKIP_H
#define ST_TEST_SKIP_H

#define ST_SKIP(...)                                                                       \
    do {                                                                                   \
        print_message("# SKIP ");                                                          \
        print_message(__VA_ARGS__);                                                        \
        print_message("\n");                                                               \
        skip();                                                                            \
    } while (0)

#endif
