/* Fitting the body model to depth frames: depth to points, finding the person, the pose and
 * shape fit, and the tracker that runs them frame after frame (docs/bodyfit.md). Included by
 * bodyfit.h; library target tryon_bodyfit_track (links OpenCV core and imgproc). */
#ifndef TRYON_FIT_TRACK_H
#define TRYON_FIT_TRACK_H

#include "bodyfit.h"

#include <stddef.h>
#include <stdint.h>

/* One depth image as bodyfit reads it (the fields of depth_frame_t). */
typedef struct fit_depth_view {
    int width, height;
    float fx, fy, cx, cy;      /* pixels */
    float metres_per_unit;     /* depth value * this = metres along the optical axis */
    const uint16_t *depth;     /* width * height, 0 = no reading */
    float camera_to_world[16]; /* row-major; camera x right, y down, z forward; world y up */
} fit_depth_view;

/* Errors of a frame, one list for the enum and the words (a test names the rejection). */
#define FIT_FRAME_ERROR_LIST(X)                                                                    \
    X(FIT_FRAME_OK, "ok")                                                                          \
    X(FIT_FRAME_SIZE, "image size is not 16..4096 x 16..4096 or differs from the first frame")     \
    X(FIT_FRAME_INTRINSICS, "intrinsics are not finite or absurd (fx, fy 50..5000 px, centre "     \
                            "inside the image)")                                                   \
    X(FIT_FRAME_UNITS, "metres_per_unit is not in 1e-5..0.1")                                      \
    X(FIT_FRAME_POSE, "camera_to_world is not a finite rigid transform")                           \
    X(FIT_FRAME_EMPTY, "no pixel has a depth reading")                                             \
    X(FIT_FRAME_NOBODY, "nobody in the working volume")                                            \
    X(FIT_FRAME_FIT, "the fit did not explain the points (track lost)")                            \
    X(FIT_FRAME_INTERNAL, "internal error")

#define FIT_FRAME_ENUM(id, text) id,
typedef enum fit_frame_error {
    FIT_FRAME_ERROR_LIST(FIT_FRAME_ENUM) FIT_FRAME_ERROR_COUNT
} fit_frame_error;
#undef FIT_FRAME_ENUM
const char *fit_frame_error_name(fit_frame_error e);
const char *fit_frame_error_text(fit_frame_error e);

/* Checks a view before anything reads its pixels: size, intrinsics, units, camera pose. */
fit_frame_error fit_depth_view_check(const fit_depth_view *v, char *why, size_t whylen);

/* ---- Finding the person ---- */
typedef struct fit_segment_desc {
    int stride;         /* 0 = 2: every stride-th pixel in x and y */
    float min_depth_m;  /* 0 = 0.5 */
    float max_depth_m;  /* 0 = 3.8: the working volume's far end (a wall at 4 m is out) */
    float max_height_m; /* 0 = 2.4: above the floor */
    float floor_band_m; /* 0 = 0.04: points this close to the floor plane are floor */
    float bg_margin_m;  /* 0 = 0.10: nearer than the learned background by this is foreground */
    int min_pixels;     /* 0 = 300 (sampled pixels): smaller components are not a person */
    uint64_t seed;      /* RANSAC's random stream */
} fit_segment_desc;

typedef struct fit_segmenter fit_segmenter;
typedef struct fit_segment {
    int width, height; /* of the sampled grid (image / stride) */
    int stride;
    const uint8_t *mask;  /* sampled grid: 1 = the person */
    const float *depth_m; /* sampled grid, 0 = no reading (flying pixels removed) */
    const float *points;  /* [count][3] world points of the person, metres */
    int count;
    float floor[4]; /* world plane n . x + d = 0, n up; floor_found */
    int floor_found;
    int components;     /* person-sized components seen (several people: the nearest the axis) */
    float centroid[3];  /* world centroid of the person */
    float top_y;        /* highest person point above the floor, m */
    int touches_border; /* the person reaches the image border (partly out of frame) */
    int touches_top;    /* the person reaches the top row: the head may be cut off */
    int touches_side;   /* the person reaches the left or right border */
} fit_segment;

fit_segmenter *fit_segmenter_create(const fit_segment_desc *d, char *err, size_t errlen);
void fit_segmenter_destroy(fit_segmenter *s);
/* Segments one checked view. Returns FIT_FRAME_OK (out describes the person),
 * FIT_FRAME_EMPTY / FIT_FRAME_NOBODY (out->count 0), or another fit_frame_error. The arrays in
 * out stay valid until the next call. The background learns from every frame outside the
 * person. */
fit_frame_error fit_segmenter_frame(fit_segmenter *s, const fit_depth_view *v, fit_segment *out,
                                    char *why, size_t whylen);

/* ---- The tracker: segmentation, fit, skinning of the published mesh ---- */
enum { FIT_STATE_INIT = 0, FIT_STATE_TRACKING = 1, FIT_STATE_LOST = 2 }; /* body_t's states */

/* Why a fit is doubted (fit_result.doubt). */
enum {
    FIT_DOUBT_UNEXPLAINED = 1, /* too many points farther than 4 cm from the model */
    FIT_DOUBT_FREE_SPACE = 2,  /* too much of the model where the camera sees through */
    FIT_DOUBT_OUT_OF_VIEW = 4, /* the person reaches the image's left or right border */
    FIT_DOUBT_LIMITS = 8,      /* joints held at their limits by the fit */
    FIT_DOUBT_SIDE_ON = 16,    /* the body turned side-on: shoulders and hips seen edge-on */
    FIT_DOUBT_LOST_PART = 32   /* unexplained points lying together: a limb left behind */
};

/* The causes' names, space-separated ("UNEXPLAINED LIMITS"), into buf. */
void fit_doubt_names(unsigned doubt, char *buf, size_t len);

/* Data points fitted per frame: 800 halved the still jitter of 400 (the depth noise averaged
 * over twice the points a limb gets) for about 1 ms of CPU a frame (docs/bodyfit.md, jitter). */
#define FIT_TRACK_POINTS 800
/* While a fit is doubted (published INIT after the person's first frames) no published joint
 * moves faster than this, m/s: a lost arm found again, or a fit flipping between two readings
 * of the same points, jumped 0.2-0.4 m a frame on the boxing clip where the true wrists moved at
 * most 0.13, and the cloth between a hand and a hip cannot follow a limb through itself
 * (docs/bodyfit.md, "Real motion"). The fastest true wrist of the project's motions and clips:
 * 3.9 m/s. */
#define FIT_TRACK_DOUBT_MPS 6.0f

typedef struct fit_tracker_desc {
    fit_segment_desc segment;
    int out_vertices;    /* 0 = 6000: the mesh published */
    int fit_vertices;    /* 0 = 1500: the coarse mesh fitted */
    int points;          /* 0 = FIT_TRACK_POINTS: data points per frame */
    int iterations;      /* 0 = 6: Gauss-Newton iterations per tracked frame */
    int init_iterations; /* 0 = 12: from the rest pose when someone enters (a restart after
                            a part was lost for good takes 40, tracker.c) */
    int start_turns;     /* 0 = 8: turns of shape and pose a frame when someone enters (all 8
                            on the first frame; fewer spread them over the first frames) */
    int shape_frames;    /* 0 = 10: frames over which the shape is estimated */
    float temporal;      /* 0 = the default (2e-4): weight of the temporal prior */
    float predict;       /* 0 = the default (1): share of the last motion carried on; < 0 none */
    float smooth_hz;     /* 0 = the default: the published pose's One Euro filter's cut-off at
                            rest (fit_smooth.h); < 0 = no filter */
    float smooth_beta_root, smooth_beta_rot; /* 0 = the defaults (fit_smooth.h) */
    float smooth_speed_hz;  /* the filter's speed estimate's cut-off; 0 = the default */
    float smooth_doubt_mps; /* while the fit is doubted, the fastest any published joint moves,
                               m/s (0 = FIT_TRACK_DOUBT_MPS; < 0 = no bound) */
    int fixed_shape;        /* 1 = use shape as given, never estimate it */
    fit_shape shape;        /* the starting (or fixed) shape; zero height = the average preset */
} fit_tracker_desc;

typedef struct fit_result {
    int state; /* FIT_STATE_* */
    fit_frame_error error;
    char message[256]; /* why a frame was not tracked */
    fit_pose pose;
    fit_shape shape;
    float joints[FIT_JOINT_COUNT * 3];
    const float *vertices; /* [vertex_count][3] world, valid until the next frame; NULL if lost */
    int vertex_count;
    const int32_t *triangles;
    int triangle_count;
    int topology_id;   /* changes when the published mesh changes (a new shape) */
    float residual_mm; /* RMS point-to-model distance of the inlier points */
    int points_used;
    /* How much to trust the body (docs/bodyfit.md, "Failure"): the share of the points the
     * model explains (within 4 cm), the share of its camera-facing vertices that lie in free
     * space, and the causes found this frame (FIT_DOUBT_* bits); a doubtful fit is published
     * with state INIT, not TRACKING, until it has been sound for a few frames again. */
    float explained, free_space;
    int unexplained_cluster; /* the most unexplained points lying together (a lost limb) */
    unsigned doubt;
    /* The frame's work: Gauss-Newton iterations of the pose (every solve this frame, the
     * measuring pass after each not counted) and shape steps (docs/bodyfit.md, "A person's
     * first frames"). */
    int iterations, shape_steps;
    double ms_segment, ms_fit, ms_skin; /* wall clock */
    /* The same three in this thread's CPU time (what a loaded machine does not inflate). */
    double cpu_ms_segment, cpu_ms_fit, cpu_ms_skin;
} fit_result;

typedef struct fit_tracker fit_tracker;
fit_tracker *fit_tracker_create(const fit_tracker_desc *d, char *err, size_t errlen);
void fit_tracker_destroy(fit_tracker *t);
/* Fits one frame. Always fills out (a bad or empty frame: state LOST, error and message set)
 * and returns out->error. */
fit_frame_error fit_tracker_frame(fit_tracker *t, const fit_depth_view *v, fit_result *out);
/* The next frame's fit starts from pose (once) instead of from the last frame's, its motion
 * carried on; the temporal prior still holds to the latter. A diagnosis, not tracking: from
 * the true pose, what the fit's own terms do to the truth (tryon-bench-fit --true-start).
 * Ignored while no person is tracked. */
void fit_tracker_start_from(fit_tracker *t, const fit_pose *pose);

/* ---- The fit itself (exposed for tests and benchmarks) ---- */
/* d(vertex)/d(parameters) of linear-blend skinning: parameters are the root translation (3)
 * and, per joint, a small rotation in world axes about the joint's world centre applied to it
 * and everything below it (3); FIT_POSE_PARAMS in all. jac: 3 x FIT_POSE_PARAMS, row-major. */
int fit_vertex_jacobian(const fit_model *m, const fit_pose *pose, int vertex, float pos_out[3],
                        double *jac);
/* Applies such a step to a pose (the local axis-angles change; the root moves). */
void fit_pose_apply_step(const fit_model *m, fit_pose *pose, const double *step);

/* Mean distance (m) from each vertex of a to the surface of b, approximated by the distance to
 * the tangent plane of b's nearest vertex (exact on flat parts; the nearest vertex alone would
 * add about half the vertex spacing). b_normals: unit normals of b. -1 without memory. */
double fit_mean_surface_distance(const float *a, int na, const float *b, const float *b_normals,
                                 int nb);

#endif
