/* cli_args.h — the render options shared by render, bench (and the
 * laboratory commands that render): parsed once, validated, with usage
 * errors printed as "strata: error: ..." (exit 2). */
#ifndef ST_CLI_ARGS_H
#define ST_CLI_ARGS_H

#include "cli_error.h"
#include "st_render.h"
#include "st_tonemap.h"

#define ST_CLI_MAX_OUTPUTS 4

typedef struct st_cli_render_args {
    st_render_options opt;
    const char *scene;  /* positional SCENE, NULL: the default scene */
    const char *output; /* -o (the last one) */
    const char *outputs[ST_CLI_MAX_OUTPUTS]; /* render: every -o, in order */
    int noutputs;
    const char *device; /* --device */
    int json;           /* bench --json */
    int cold;           /* bench --cold: time the kernel build in an empty cache too */
    int rays;           /* bench --rays: 1 + ST_RAYS_*; 0: bench a render */
    unsigned ray_count; /* bench --count (0: not given) */
    int scene_list;     /* --scene-list */
    int quiet;          /* --quiet: no progress bar, no summary */
    int scramble_given; /* --scramble seen (for its error) */
    int depth_given;    /* --max-depth seen; else the scene's default (st_render_default_depth) */
    const char *spp_map;      /* --spp-map FILE.png */
    const char *adaptive_opt; /* an adaptive-only option seen (for its error) */
    st_u32 threads;           /* --threads N; 0: every compute unit */
    st_u32 lanes;             /* --lanes N; 0: auto (st_render_lanes_recall, _measure) */
    int said;                 /* the scene's warnings and notes are printed already (a
                                 second session of one command opens it quietly) */
    float exposure;           /* --exposure EV (PNG) */
    st_u32 tonemap;           /* --tonemap: an st_tonemap (PNG) */
    const char *png_opt;      /* a PNG-only option seen (for its error) */
    st_u32 part_k, part_n;    /* --part K/N (already applied as opt's sample range);
                                 part_n 0: not given */
    const char *env_file;     /* --env FILE.exr|FILE.hdr (the session reads it); NULL: none */
    st_u32 aovs;              /* --aov: bit k for ST_AOV_* k (render only) */
    const char *display_server; /* --display-server HOST:PORT (render only); NULL: none */
} st_cli_render_args;

/* Parses argv (argv[0] is the subcommand). bench: 0 for render; 1 for bench
 * (--json, no -o); 2 for converge (neither).
 * Returns ST_CLI_OK, ST_CLI_HELP (help printed) or ST_CLI_EXIT_USAGE. */
int st_cli_parse_render_args(int argc, char **argv, int bench, st_cli_render_args *a);

/* Filter parameters as given on a command line (NULL: not given), checked
 * against the filter kind already in *f (a parameter the filter does not
 * take is a usage error) and applied over its defaults. */
typedef struct st_cli_filter_args {
    const char *radius, *b, *c, *sigma, *tau;
} st_cli_filter_args;
int st_cli_apply_filter_args(const st_cli_filter_args *fa, st_filter *f);

/* A field as library messages name it ("filter radius") and the option that
 * sets it ("--filter-radius"): the library names fields, the CLI its flags. */
typedef struct st_cli_option_name {
    const char *field, *option;
} st_cli_option_name;
/* The fields of st_render_options that st_render_check names, with the
 * options of render, bench and converge (and signal's filter options);
 * ends with {NULL, NULL}. */
extern const st_cli_option_name st_cli_render_option_names[];
/* Rewrites, in place, the field that opens err's message ("filter radius 9:
 * ...") as its option ("--filter-radius 9: ...") when names lists it;
 * returns whether it did. */
int st_cli_option_words(st_error *err, const st_cli_option_name *names);
/* st_cli_fail, with the field that opens err's message ("filter radius 9:
 * ...") written as its option ("--filter-radius 9: ...") when names lists it. */
int st_cli_fail_options(const st_error *err, const st_cli_option_name *names);

/* Strict numbers: the whole string must parse; else a usage error naming opt. */
int st_cli_parse_u32(const char *opt, const char *s, unsigned lo, unsigned hi, unsigned *out);
int st_cli_parse_float(const char *opt, const char *s, float *out);

#endif
