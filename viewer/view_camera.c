/* Camera moves of lanecast view, in pixels of the render image. The camera
 * stays an lc_camera (eye, at, up) that lanecast render takes as flags; the
 * library builds the rays from it. Orbit is a turntable about `at` around
 * the camera's up vector, which never changes, so the printed camera keeps
 * the up the user gave. */
#include <math.h>
#include <stdio.h>
#include "render_opts.h"
#include "view.h"

static lc_vec3 sub(lc_vec3 a, lc_vec3 b) { return (lc_vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static lc_vec3 add(lc_vec3 a, lc_vec3 b) { return (lc_vec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static lc_vec3 scale(lc_vec3 a, float s) { return (lc_vec3){a.x * s, a.y * s, a.z * s}; }
static float dot(lc_vec3 a, lc_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static lc_vec3 cross(lc_vec3 a, lc_vec3 b)
{
    return (lc_vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static lc_vec3 unit(lc_vec3 a)
{
    float n = sqrtf(dot(a, a));
    return n > 0.0f ? scale(a, 1.0f / n) : (lc_vec3){0.0f, 1.0f, 0.0f};
}
static lc_vec3 up_of(const lc_camera *c)
{
    return dot(c->up, c->up) > 0.0f ? unit(c->up) : (lc_vec3){0.0f, 1.0f, 0.0f};
}
static float fov_rad(const lc_camera *c) { return (c->fovy > 0.0f ? c->fovy : 40.0f) * 3.14159265f / 180.0f; }

void view_cam_orbit(lc_camera *c, float dx_px, float dy_px, int height)
{
    const float per_px = 3.14159265f / (float)(height > 0 ? height : 1); /* the window's height = half a turn */
    lc_vec3 up = up_of(c), d = sub(c->eye, c->at);
    d = render_rotate(d, up, -dx_px * per_px);
    lc_vec3 right = cross(d, up);
    if (dot(right, right) > 0.0f) {
        lc_vec3 e = render_rotate(d, unit(right), dy_px * per_px);
        /* stop short of the poles: a view along up has no right vector */
        if (fabsf(dot(unit(e), up)) < 0.999f) d = e;
    }
    c->eye = add(c->at, d);
}

void view_cam_pan(lc_camera *c, float dx_px, float dy_px, int height)
{
    lc_vec3 up = up_of(c), fwd = unit(sub(c->at, c->eye));
    lc_vec3 right = cross(fwd, up);
    if (!(dot(right, right) > 0.0f)) return;
    right = unit(right);
    lc_vec3 upv = cross(right, fwd);
    float span = c->projection == LC_ORTHOGRAPHIC ? c->height
                                                  : 2.0f * sqrtf(dot(sub(c->at, c->eye), sub(c->at, c->eye))) *
                                                        tanf(0.5f * fov_rad(c));
    float per_px = span / (float)(height > 0 ? height : 1);
    lc_vec3 move = add(scale(right, -dx_px * per_px), scale(upv, dy_px * per_px));
    c->eye = add(c->eye, move);
    c->at = add(c->at, move);
}

void view_cam_zoom(lc_camera *c, float steps)
{
    float f = powf(0.9f, steps); /* one wheel step: 10% closer */
    if (c->projection == LC_ORTHOGRAPHIC) {
        if (c->height > 0.0f) c->height = fmaxf(c->height * f, 1e-6f);
        return;
    }
    lc_vec3 d = scale(sub(c->eye, c->at), f);
    if (dot(d, d) > 1e-12f) c->eye = add(c->at, d);
}

void view_cam_format(const lc_camera *c, char *out, size_t n)
{
    lc_vec3 up = dot(c->up, c->up) > 0.0f ? c->up : (lc_vec3){0.0f, 1.0f, 0.0f};
    int k = snprintf(out, n, "--eye %.9g,%.9g,%.9g --at %.9g,%.9g,%.9g --up %.9g,%.9g,%.9g", (double)c->eye.x,
                     (double)c->eye.y, (double)c->eye.z, (double)c->at.x, (double)c->at.y, (double)c->at.z,
                     (double)up.x, (double)up.y, (double)up.z);
    if (k < 0 || (size_t)k >= n) return;
    if (c->projection == LC_ORTHOGRAPHIC) snprintf(out + k, n - (size_t)k, " --ortho %.9g", (double)c->height);
    else snprintf(out + k, n - (size_t)k, " --fov %.9g", (double)(c->fovy > 0.0f ? c->fovy : 40.0f));
}
