/* tryon-sim's rehearsal before it listens: a person's first body makes the garment and builds the
 * body's collision state (its tree and adjacency), and on this project's machines the fresh pages
 * that state touches cost more than the work (about 11 us a page: tryon_heap.h). */
#include "rehearse.h"

#include <stdio.h>
#include <stdlib.h>

#include "bodyfit.h"
#include "outfit_pattern.h"

sim *sim_rehearse(const sim_outfit *worn, const sim_desc *desc, int verts, char *err,
                  size_t err_size)
{
    sim_reject why = {0};
    sim_outfit o = *worn;
    if (o.is_pattern && sim_outfit_resolve("shirt", o.size, o.fabric_name, &o, &why) < 0) {
        snprintf(err, err_size, "%s", why.detail);
        return NULL;
    }
    fit_model *m =
        fit_model_create(&(fit_model_desc){.shape = fit_shape_default(),
                                           .target_vertices = SIM_REHEARSE_BODY_VERTICES},
                         err, err_size);
    if (!m)
        return NULL;
    int nv = fit_model_vertex_count(m), nt = fit_model_triangle_count(m);
    const int32_t *tris = fit_model_triangles(m);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz), joints[FIT_JOINT_COUNT * 3];
    fit_pose pose;
    fit_motion_eval(FIT_MOTION_STILL, 0.0, &pose);
    sim_garment g = {0};
    sim *s = NULL;
    if (!xyz || fit_model_pose(m, &pose, xyz, joints) < 0) {
        snprintf(err, err_size, "the stand-in body could not be posed");
        goto done;
    }
    if (sim_outfit_make(&o, xyz, nv, tris, nt, joints, verts, &g, &why) < 0) {
        snprintf(err, err_size, "%s on the stand-in body: %s", o.id, why.detail);
        goto done;
    }
    sim_desc d = *desc;
    d.backend = SIM_BACKEND_C; /* the host's memory is what is rehearsed */
    d.fabric = o.fabric;
    if (worn->is_pattern) /* the pattern's contact thickness, or its sim takes nothing */
        d.thickness_m = sim_pattern_thickness_m();
    s = sim_create(&d, &g, &why);
    if (!s || sim_start(s, xyz, nv, tris, nt, NULL, &why) < 0 ||
        sim_step(s, xyz, nv, tris, nt, NULL, &why) < 0) {
        snprintf(err, err_size, "%s on the stand-in body: %s", o.id, why.detail);
        sim_destroy(s);
        s = NULL;
    }
done:
    sim_garment_free(&g);
    free(xyz);
    fit_model_destroy(m);
    return s;
}
