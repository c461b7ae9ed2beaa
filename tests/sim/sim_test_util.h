/* Helpers shared by the test_sim_* tests: scenes small enough for the sanitizer build, and the
 * backends to run each test body on (STYLE.md 14). */
#ifndef TRYON_SIM_TEST_UTIL_H
#define TRYON_SIM_TEST_UTIL_H

#include "scene.h"
#include "sim.h"

/* The backends built into this binary whose device opens here. */
int simt_backends(sim_backend out[2]);
const char *simt_backend_name(sim_backend b);

/* The drape scene at test size: n x n sheet of side 0.6 m, 0.15 m above a 0.2 m sphere. */
sim *simt_drape(sim_backend b, sim_solver solver, int n, const sim_desc *over);
sim_scene *simt_sphere(void);
/* Steps frames on a fixed body; returns the worst penetrating count, -1 on an error. */
int simt_run(sim *s, sim_scene *sc, int frames, sim_frame_stats *last);
int simt_all_finite(const sim *s);
float simt_max_speed(const sim *s, float frame_dt); /* m/s from the last step */
/* The body scene's motion (a body of body_verts) into *sc, and the shirt of shirt_verts with
   hem_m (sim_garment_shirt) made on its frame 0 into g; that frame's vertex and triangle counts
   into nv, nt. Returns sim_garment_shirt's result, or -SIM_ERR_PARAM without a scene. */
int simt_scene_shirt(const char *motion, int body_verts, int shirt_verts, float hem_m,
                     sim_scene **sc, sim_garment *g, int *nv, int *nt);
/* How far (m) attachment a's vertex lies in s from the attachment's place on the body (xyz, tris:
   [n][3]): the foot b0 v0 + b1 v1 + b2 v2 on its triangle, offset along the triangle's normal. */
float simt_attachment_off_m(const sim *s, const sim_attachment *a, const float *xyz,
                            const int32_t *tris);
#endif
