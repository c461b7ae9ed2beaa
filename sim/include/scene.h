/* Private to sim/: the benchmark and test scenes' bodies. A scene body is a triangle mesh that
 * moves with time: a fixed sphere, or the bodyfit model in scripted motion (a capsule figure
 * when bodyfit is not linked). */
#ifndef TRYON_SIM_SCENE_H
#define TRYON_SIM_SCENE_H

#include <stdint.h>

typedef struct sim_scene sim_scene;

/* A UV sphere of about n_triangles (closed, counter-clockwise from outside). */
sim_scene *sim_scene_sphere(float radius_m, const float centre[3], int n_triangles);
/* The body model playing motion ("all" = still, arm_raise, turn, walk, fast_swing in turn, 3-4 s
 * each, each ending in the pose it started from and crossfading from the one before over 0.5 s).
 * A motion ending in ".bvh" is a motion-capture file retargeted onto the model (bodyfit.h,
 * fit_clip); one ending in ".lcmlog" a recorded session's bodies (sim_scene_log). NULL with err
 * filled when the motion is unknown or the file refused. */
sim_scene *sim_scene_body(const char *motion, int target_vertices, char *err, size_t err_size);
void sim_scene_destroy(sim_scene *sc);
/* Bodies as they were recorded: frames bodies of nv vertices sharing one triangle list (copied),
 * xyz frames * nv * 3 floats and joints frames * joint_floats floats (0 .. 32 * 3; NULL for none).
 * On success the scene owns xyz and joints (malloc'd); on failure (NULL) the caller still does.
 * Frame k is the body from (k - 1/2) to (k + 1/2) * frame_dt_s; after the last, the last. */
sim_scene *sim_scene_recorded(int nv, const int32_t *tris, int nt, int frames, float *xyz,
                              float *joints, int joint_floats, double frame_dt_s);
/* A recorded session's bodies (motion FILE.lcmlog of sim_scene_body): every BODY an lcm-logger
 * log holds (tryon run --record, or lcm-logger beside any pipeline; the bus's tags checked), in
 * order, one a frame at 30 fps, from the first body published tracking (before it the fitter's
 * shape is not settled: tryon-sim dresses the garment again there); lost bodies (no vertices)
 * skipped, the triangle list and vertex count those of the first body kept. NULL with err naming
 * the log and what is wrong. */
sim_scene *sim_scene_log(const char *path, char *err, size_t err_size);

/* Pose the body at time t_s. The arrays stay valid until the next call. joints: FIT_JOINT_COUNT
 * * 3 floats, or NULL for bodies without a skeleton. Returns 0 or -1. */
int sim_scene_eval(sim_scene *sc, double t_s, const float **xyz, int *nv, const int32_t **tris,
                   int *nt, const float **joints);
double sim_scene_duration(const sim_scene *sc); /* seconds of motion before it loops */
/* "all": which segment plays at t_s (0 .. sim_scene_segment_count() - 1) and, in local_s (may be
 * NULL), the time into it; -1 (local_s = t_s) for any other scene. */
int sim_scene_segment(const sim_scene *sc, double t_s, double *local_s);
int sim_scene_all_segment(double t_s, double *local_s); /* the same for "all", without a scene */
int sim_scene_segment_count(void);
const char *sim_scene_segment_name(int k); /* "still", ...; "none" out of range */

#endif
