/* cli_session.h — what the subcommands that render share (render, bench,
 * converge, merge): opening the device, scene and renderer, the error of a
 * failed session, the EXR header and RGB image of a render, and the one-line
 * summary. Used by subcommands; uses only the argument parser, the error
 * helpers and the library. */
#ifndef ST_CLI_SESSION_H
#define ST_CLI_SESSION_H

#include "cli_args.h"
#include "st_device.h"
#include "st_envmap.h"
#include "st_image.h"
#include "st_render.h"
#include "st_scene.h"

/* Everything a render needs, opened in order; st_cli_session_close releases
 * what was opened. */
typedef struct st_cli_session {
    st_device *dev;
    st_scene *scene;
    st_renderer *renderer;
    st_envmap *env_map; /* --env FILE; NULL: none */
    double load_seconds;
    double build_seconds; /* the program's build and the first launch of its kernels */
    st_lanes_choice lanes; /* the kernels' lane width and how it was chosen */
    double lanes_seconds;  /* the calibration's time, where this session measured it */
} st_cli_session;

/* Opens the session of a's render: the scene, --env's map (recorded in
 * a->opt.env_map, so that every render of a's options sees it), the
 * device and the renderer. */
st_status st_cli_session_open(st_cli_render_args *a, st_cli_session *s, st_error *err);
void st_cli_session_close(st_cli_session *s);
/* The lighting default, said: one `strata: note:` naming the default a
 * render without --env takes (st_scene.env_default) and the option that
 * changes it; a `strata: warning:` when nothing lights the render at all. */
void st_cli_light_notes(const st_scene *scene, const st_render_options *o);
/* One `strata: note:` line when an adaptive request for o's sampler is
 * rendered uniformly instead (st_render_adaptive_falls_back says why). */
void st_cli_adaptive_note(const st_render_options *o);
/* One `strata: note:` line after a render whose QMC sampler's pilot
 * predicted no gain from adapting, so that it went on uniformly
 * (st_render_stats.adaptive_uniform). */
void st_cli_adaptive_no_gain_note(const st_render_options *o, const st_render_stats *st);
/* The words the note and the EXR header give for that fallback. */
#define ST_CLI_ADAPTIVE_FALLBACK "its stratification across a pixel's samples is lost when pixels get different counts, so adaptive sampling would lose to uniform at equal cost"
/* The words the note (after the render's summary) and the EXR header give
 * when a QMC sampler's pilot predicts that adapting would not pay. */
#define ST_CLI_ADAPTIVE_NO_GAIN "its pilot predicted adaptive counts no better than uniform ones here, so it went on uniformly"
/* Prints the error (and a kernel build's compiler log); returns the exit status. */
int st_cli_session_fail(const st_cli_session *s, const st_error *err);
/* Rewrites an error of st_device_create in the CLI's words: the device
 * module names its field ("device xyz: ..."), the CLI its flag and where the
 * choices are listed ("--device xyz: ... (see `strata devices`)").
 * Returns err->status. */
st_status st_cli_device_words(st_error *err);

/* The render's settings as "strata.*" EXR attributes; returns the count. */
#define ST_CLI_MAX_ATTRS 40
int st_cli_render_attrs(const st_cli_render_args *a, const st_cli_session *s,
                        const st_render_stats *st, st_attr *attrs);
/* Drops the facts of the run (render time, device) from attrs, keeping the settings in order, so
 * that a PNG made twice is the same file; returns the new count. */
int st_cli_settings_only(st_attr *attrs, int n);
/* For a PNG: applies --exposure and --tonemap to rgb (3 channels) and makes attrs the settings
 * (st_cli_settings_only) with strata.exposure and strata.tonemap added (attrs has room for
 * ST_CLI_MAX_ATTRS); returns the new count. */
int st_cli_png_settings(const st_cli_render_args *a, st_image *rgb, st_attr *attrs, int n);
/* The R, G, B channels of a render (its W channel dropped). */
st_status st_cli_rgb_of(const st_image *in, st_image *out, st_error *err);
/* Whether path ends in ext, ignoring case. */
int st_cli_has_extension(const char *path, const char *ext);

/* Prints the built-in scene names, one per line. */
void st_cli_print_scene_list(void);

/* st_render of o with its own progress on stderr under label (the
 * reference of converge and compare, which takes as long as the study
 * itself). */
st_status st_cli_render_with_progress(const st_cli_session *s, const st_render_options *o,
                                      const char *label, int quiet, st_image *img,
                                      st_error *err);

/* Monotonic seconds, for the load, build and render times. */
double st_cli_now(void);

/* The one-line summary: time, samples/s, rays/s, clamps; with
 * compile_seconds >= 0 also the time the kernels took to compile before the
 * render (the session's build_seconds), which the render's time leaves out. */
void st_cli_print_summary(const char *what, const st_render_options *o,
                          const st_render_stats *st, double compile_seconds);

#endif
