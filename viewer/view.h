/* lanecast view: a window that renders data progressively, on the public
 * API only (include/lanecast/lanecast.h). Threads:
 * - the UI thread (view_gui.cpp: GLFW, Dear ImGui, OpenGL 2.1) handles input,
 *   changes the wanted state (view_state.want) through the actions below and
 *   shows the latest finished pass; it never waits for a render;
 * - the render-control thread (view_render.c) turns each new wanted state
 *   into a render job (lc_render_begin), cancelling the one before;
 * - the histogram thread (view_hist.c) computes the TF editor's histogram;
 * - the frame loader (view_frames.c) loads the next frame of a trajectory.
 * Mouse, keys and --script commands all go through view_action.c, so a
 * script exercises the same code as a user. */
#ifndef LC_VIEW_H
#define LC_VIEW_H

#include <pthread.h>
#include <stdint.h>
#include "lanecast/lanecast.h"

#define VIEW_MAX_POINTS 64 /* opacity points per field in the editor */
#define VIEW_HIST_BINS 128

/* The transfer function as plain data (the editor changes it; the render
 * thread builds an lc_tf from it). */
typedef struct view_tf {
    int nfields;
    int ncolor[LC_MAX_FIELDS], nopacity[LC_MAX_FIELDS];
    float color[LC_MAX_FIELDS][4 * 256];
    float opacity[LC_MAX_FIELDS][2 * VIEW_MAX_POINTS];
    int has_range[LC_MAX_FIELDS];
    float range[LC_MAX_FIELDS][2];
    float opacity_scale; /* multiplies every tau when the TF is built (1 = as given) */
    char colormap[32];   /* the preset the colours came from ("" = the input's own) */
} view_tf;

/* Everything a frame depends on; the UI changes it, the render thread reads
 * a copy. Versions say what changed since the last copy. */
typedef struct view_want {
    lc_render_desc rd;       /* camera, size, mode, shading, dt, ...; tf and volume unset */
    view_tf tf;
    lc_particle_params pp;   /* particles only; applied between jobs */
    lc_target target;
    int threads;
    int nav;                 /* 1: render at navigation quality */
    int nav_scale;           /* pixel scale of navigation frames (2..16) */
    float nav_step;          /* step multiplier of navigation frames (>= 1) */
    uint64_t gen;            /* bumped by every change */
    uint64_t tf_gen, pp_gen, dev_gen, vol_gen;
} view_want;

/* The latest finished pass, as the UI shows it. */
typedef struct view_shown {
    float *rgba;             /* width * height * 4, premultiplied */
    int width, height;
    uint64_t gen;            /* the want.gen it was rendered for */
    uint64_t seq;            /* bumped by every new pass */
    int pass, npasses, scale, final, nav;
    double pass_seconds;     /* since the job began */
    lc_render_stats stats;   /* of the last finished job */
    double job_seconds;
    uint64_t stats_gen;
    lc_target target;
    int threads;
    char error[512];         /* the last render error, "" if none */
    uint64_t failed_gen;     /* the want.gen whose job could not begin (0 = none) */
} view_shown;

typedef struct view_hist {
    int ready, nfields;
    float log_counts[LC_MAX_FIELDS][VIEW_HIST_BINS]; /* log(1 + count), normalised to max 1 */
    float range[2];                                  /* values the bins span */
} view_hist;

typedef enum view_drag_kind { VIEW_DRAG_NONE = 0, VIEW_DRAG_ORBIT, VIEW_DRAG_PAN } view_drag_kind;

typedef struct view_state {
    pthread_mutex_t mu;      /* guards want, shown, hist, frame, quit and the messages */
    pthread_cond_t cv;       /* want changed or a job ended: wakes the render thread */
    view_want want;
    view_shown shown;
    view_hist hist;
    int hist_busy;           /* the histogram thread still reads the first frame's volume */
    float *refined;          /* copy of the latest full-quality frame of the current want */
    uint64_t refined_gen;    /* want.gen of it (0 = none yet) */
    int quit;
    void (*wake)(void);      /* wakes the UI thread (any thread may call it) */
    pthread_mutex_t vol_mu;  /* held while the histogram samples and while params change */

    /* set up before the threads start, then read-only */
    const char *cmd, *input;
    lc_volume *volume;       /* the current frame's volume (render thread's; swapped between jobs) */
    lc_tf *initial_tf;       /* the TF as `lanecast render` builds it, rendered until the first edit */
    lc_volume_info vinfo;
    lc_camera home;          /* `r` goes back here */
    lc_vec3 background;
    int alpha;
    int size_fixed;          /* --size given: render at that size, not the framebuffer's */

    /* frames of a trajectory (view_frames.c) */
    lc_device *ui_dev;       /* the UI thread's own device (TF presets, saving) */
    lc_device *load_dev;     /* loaded the first frame (the loader has its own) */
    void *ro;                /* the parsed lanecast render options (ropts) */
    const void *kind;        /* the input's cli_kind row */
    lc_volume *retired;      /* a frame's volume the render thread let go of */
    int64_t frame, frames;
    int64_t frame_loading;   /* -1: none */
    int64_t frame_want;      /* asked for, not yet being loaded (-1: none) */
    int64_t next_frame;      /* the frame of next_volume */
    lc_device *frames_dev;   /* the loader's device (its volumes are destroyed before it) */
    int playing;
    lc_volume *next_volume;  /* loaded, waiting for the render thread to take it */
    char frame_error[512];

    /* navigation (UI thread only) */
    view_drag_kind drag;
    double last_x, last_y;
    double release_at;       /* a wheel's "release": when to refine (0 = none pending) */
    double refine_delay;     /* seconds from release to the full frame (default 0) */
    int adaptive;            /* adapt nav_scale to hold target_ms */
    float target_ms;
    int min_nav_scale;
    int show_ui, show_box;
    int panels_open, panels_asked; /* the controls window expanded; asked to change */
    int plane_axis;          /* slice plane: normal along x, y or z */
    float plane_pos;         /* its position across the box, 0..1 */
    int save_pending;        /* `s` presses waiting for the refined frame */
    int quit_asked;          /* q/Esc: quit once pending saves are written */
    int saved_count;         /* for lanecast-view-NNN.png */
    char status[4608];       /* the last message the overlay shows (may hold a path) */
} view_state;

double view_now(void);

/* view_camera.c: camera moves in pixels of the render image. */
void view_cam_orbit(lc_camera *c, float dx_px, float dy_px, int height);
void view_cam_pan(lc_camera *c, float dx_px, float dy_px, int height);
void view_cam_zoom(lc_camera *c, float steps);
/* "--eye X,Y,Z --at X,Y,Z --up X,Y,Z --fov F" (or --ortho H), %.9g. */
void view_cam_format(const lc_camera *c, char *out, size_t n);

/* view_action.c: every change of the wanted state (lock held inside). */
void view_drag_begin(view_state *v, view_drag_kind k, double x, double y);
void view_drag_move(view_state *v, double x, double y);
void view_drag_end(view_state *v);
void view_wheel(view_state *v, double steps);
void view_reset(view_state *v);
void view_tick(view_state *v); /* per UI frame: pending releases, adaptation, frame play */
/* The next navigation frame's pixel scale after one of ms at scale s (view_action.c). */
int view_next_scale(int s, double ms, double target_ms, int smin);
void view_set_size(view_state *v, int w, int h);
/* Call with v->mu held after changing v->want: bumps the generation and wakes the render thread. */
void view_changed(view_state *v);
/* Saves the refined frame: path NULL = the next free lanecast-view-NNN.png.
 * 0 ok, -1 (message in v->status and on stderr) failed or no refined frame. */
int view_save(view_state *v, lc_device *dev, const char *path);
void view_print_camera(view_state *v);
/* 1 when the job of the current view could not begin (shown.error says why). */
int view_failed(view_state *v);
/* 1 when the frame of the current view is refined (no move and no frame load pending). */
int view_refined(view_state *v);
int view_key(view_state *v, const char *key); /* "r", "s", "c", "h", "q", ...: 1 handled */
/* name = value through the same bounds as the panels (view_set_names lists
 * them); 0 ok, -1 unknown name or bad value (message on stderr). */
int view_set(view_state *v, const char *name, const char *value);
/* Replaces (or adds, at index = count) opacity point index of field f,
 * keeping v sorted; tau clamped to >= 0. */
/* Numbers by name, clamped to the panel's bounds (view_param_bounds: 0, or
 * -1 for an unknown name). */
int view_param_bounds(const view_state *v, const char *name, float *lo, float *hi, int *integer);
float view_getf(view_state *v, const char *name);
int view_setf(view_state *v, const char *name, float x);
extern const char *const view_modes[4], *const view_shadings[3], *const view_methods[5];
void view_tf_point(view_state *v, int f, int index, float x, float tau);
void view_tf_delete_point(view_state *v, int f, int index);
int view_tf_colormap(view_state *v, const char *name); /* 0 ok, -1 unknown */
int view_tf_save(view_state *v, const char *path);      /* SPEC.md JSON; 0 ok, -1 failed */

/* view_render.c */
int view_render_start(view_state *v);
void view_render_stop(view_state *v);
/* An lc_tf from the plain description (on dev). */
lc_status view_tf_build(lc_device *dev, const view_tf *t, lc_tf **out);
void view_tf_from(view_tf *t, const lc_tf *tf);

/* view_hist.c: starts the background histogram (never blocks). */
int view_hist_start(view_state *v);
void view_hist_stop(view_state *v);

/* view_script.c: --script commands, one per call, through the actions.
 * Returns 1 while running, 0 at the end, -1 on a bad line (message printed). */
typedef struct view_script view_script;
view_script *view_script_open(const char *path, const char *cmd);
int view_script_step(view_script *s, view_state *v, lc_device *dev);
int view_script_waiting(const view_script *s); /* 1: in a wait or sleep (the UI may block for events) */
void view_script_close(view_script *s);

/* view_frames.c: frames of a trajectory, loaded in the background.
 * cmd: "frame" (go to n), "step" (by n), "play", "pause"; 0 ok, -1 bad. */
int view_frames_command(view_state *v, const char *cmd, long long n);
int view_frames_start(view_state *v);
/* The render thread takes a loaded frame between jobs (mu held); NULL: none. */
lc_volume *view_frames_take(view_state *v, int64_t *frame);
void view_frames_tick(view_state *v); /* UI thread, mu held: playback */
void view_frames_stop(view_state *v);

/* view_gui.cpp: runs the window until quit; returns the exit status. */
typedef struct view_run {
    view_state *v;
    lc_device *ui_dev;       /* the UI thread's own device (saving images) */
    view_script *script;
    const char *screenshot;  /* --screenshot PATH */
} view_run;
int view_gui_run(view_run *r);
void view_gui_close(void); /* after the other threads have stopped */
void view_gui_wake(void);  /* any thread: the UI looks at the state again */

#endif
