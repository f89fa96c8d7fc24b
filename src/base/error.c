/* error.c — the one place that formats error messages (see st_error.h). */
#include "st_error.h"

#include <stdarg.h>
#include <stdio.h>

st_status st_fail(st_error *err, st_status s, const char *fmt, ...)
{
    if (!err)
        return s;
    if (err->status != ST_OK)
        return err->status;
    err->status = s;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    return s;
}

void st_error_clear(st_error *err)
{
    if (err) {
        err->status = ST_OK;
        err->msg[0] = '\0';
    }
}

const char *st_status_text(st_status s)
{
#define ST_AS_TEXT(name, text) case name: return text;
    switch (s) { ST_STATUS_LIST(ST_AS_TEXT) }
#undef ST_AS_TEXT
    return "unknown";
}
