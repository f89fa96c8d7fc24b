/* cli_display.h — the live view of --display-server HOST:PORT: the image
 * sent to a viewer speaking tev's protocol (Tom94/tev, include/tev/Ipc.h
 * and src/Ipc.cpp) over TCP while it renders, as pbrt-v4's --display-server
 * does. Packets are length-prefixed and little-endian: a uint32 byte count
 * (itself included), a type byte, then the fields; strings end in NUL. Once
 * per connection CreateImage (4: grabFocus, name, int32 width, height,
 * channel count, channel names); then UpdateImageV3 (6: grabFocus, name,
 * int32 channel count, channel names, int32 x, y, width, height, int64
 * offset and stride per channel, float32 samples) for every tile of the
 * image, each time the renderer shows its film (at most every
 * ST_CLI_DISPLAY_SECONDS) and once with the final image.
 * The viewer is a bystander: a connection that fails or drops is one
 * warning (the first time) and a new try at a later look, never an error,
 * and nothing sent changes the image written. */
#ifndef ST_CLI_DISPLAY_H
#define ST_CLI_DISPLAY_H

#include <stddef.h>

#include "st_image.h"

#define ST_CLI_DISPLAY_SECONDS 0.25 /* between two looks at the film, at least */
#define ST_CLI_DISPLAY_RETRY 1.0    /* between two tries to connect, at least */
#define ST_CLI_DISPLAY_TILE 64      /* a tile's side, pixels */

typedef struct st_cli_display {
    char spec[300];          /* HOST:PORT as given, for messages */
    char host[256], port[16];
    char name[256];          /* the image's name in the viewer */
    unsigned width, height;  /* the whole image (a crop's window is placed in it) */
    int fd;                  /* the connection; -1: none */
    int warned;              /* a warning was printed */
    double next_try;         /* monotonic seconds: no connection is tried before */
} st_cli_display;

/* Splits HOST:PORT (PORT 1..65535; HOST a name, an IPv4 address or an IPv6
 * one in brackets); 0, or a usage error printed (ST_CLI_EXIT_USAGE). */
int st_cli_display_parse(const char *spec, char *host, size_t host_cap, char *port,
                         size_t port_cap);
/* A display of a width x height image named name at spec (parsed already);
 * nothing is connected yet. */
void st_cli_display_init(st_cli_display *d, const char *spec, const char *name, unsigned width,
                         unsigned height);
/* Connects and announces the image (CreateImage) before the render starts, so
 * the viewer shows it at once; trouble is the one warning, and a later look
 * tries again. */
void st_cli_display_open(st_cli_display *d);
/* Sends img (R, G, B, placed by its x0, y0 in the image), connecting first
 * where there is no connection and a try is due (final: try now). Never
 * fails: trouble is a warning, once. */
void st_cli_display_show(st_cli_display *d, const st_image *img, int final);
/* The renderer's preview callback (st_preview_fn): ctx is an st_cli_display. */
void st_cli_display_preview(void *ctx, const st_image *so_far);
void st_cli_display_close(st_cli_display *d);

#endif
