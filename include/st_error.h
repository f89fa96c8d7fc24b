/* st_error.h — status codes and one-line error messages for every module.
 *
 * Library code never prints or exits: a fallible function returns st_status and
 * fills the st_error passed last with one line naming what and where. The first
 * error recorded wins, so cleanup code cannot overwrite the root cause. Only the
 * CLI prints "strata: error: <msg>" and picks the exit status (2 for usage, 1
 * otherwise). */
#ifndef ST_ERROR_H
#define ST_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

#define ST_STATUS_LIST(X)                                                    \
    X(ST_OK, "ok")                                                           \
    X(ST_ERR_USAGE, "usage")                                                 \
    X(ST_ERR_IO, "i/o")                                                      \
    X(ST_ERR_FORMAT, "bad input")                                            \
    X(ST_ERR_DEVICE, "opencl")                                               \
    X(ST_ERR_NOMEM, "memory")                                                \
    X(ST_ERR_CHECK, "check failed")

#define ST_AS_ENUM(name, text) name,
typedef enum st_status { ST_STATUS_LIST(ST_AS_ENUM) } st_status;
#undef ST_AS_ENUM

typedef struct st_error {
    st_status status;
    char msg[512];
} st_error;

/* Records status s and a printf-style message in err unless an error is already
 * recorded (first error wins). Returns the status now held by err. err may be
 * NULL. */
st_status st_fail(st_error *err, st_status s, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Clears err to ST_OK with an empty message. */
void st_error_clear(st_error *err);

/* Static text of a status code ("bad input", ...). */
const char *st_status_text(st_status s);

#ifdef __cplusplus
}
#endif

#endif
