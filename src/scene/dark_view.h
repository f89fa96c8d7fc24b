/* dark_view.h — how much of a scene's default view its own lights leave
 * dark (src/scene/dark_view.c): what decides whether the lighting default
 * keeps a dim environment (scene.c, choose_default_env). Private to the
 * scene module. */
#ifndef ST_DARK_VIEW_H
#define ST_DARK_VIEW_H

#include "st_error.h"
#include "st_scene.h"

/* The fraction (0..1) of a grid of the default camera's rays whose point no
 * light of the scene reaches directly (or that leave the scene), with no
 * environment. Needs s's triangles, materials, punctual lights, bounds and
 * default camera. ST_ERR_NOMEM. */
st_status st_scene_dark_fraction(const st_scene *s, double *fraction, st_error *err);

/* The distance from the default camera within which the nearest tenth of
 * what the same grid of its rays meets lies (the tenth percentile), in
 * *distance; 0 where no ray meets anything. ST_ERR_NOMEM. */
st_status st_scene_view_distance(const st_scene *s, double *distance, st_error *err);

#endif
