/* A sewing pattern dressed on the body model and carried to the body's pose (outfit_pattern.h).
 * The dressing needs a fit_model: the one made from the body message's shape, which is the model
 * bodyfit fitted; its rest pose is where gar_dress_tryon works, the message's pose where the sim
 * starts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bodyfit.h"
#include "carry.h"
#include "garments.h"
#include "outfit_pattern.h"
#include "pattern_hold.h"
#include "pattern_weld.h"

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

/* [n][3] -> [n][4] (w unused). NULL when out of memory. */
static float (*padded(const float *xyz, int n))[4]
{
    float(*p)[4] = malloc((size_t)n * sizeof *p);
    for (int i = 0; p && i < n; i++)
        for (int k = 0; k < 4; k++)
            p[i][k] = k < 3 ? xyz[i * 3 + k] : 0.0f;
    return p;
}

/* The dressed mesh moved with the model from rest to the posed vertices (the model's topology;
 * sim/carry.c: each point with the body vertex nearest it, turned as that vertex's triangle
 * turned). */
static int carry_to(const fit_model *body, const float *posed, gar_mesh *m, sim_reject *why)
{
    int nv = fit_model_vertex_count(body), nt = fit_model_triangle_count(body);
    float(*from)[4] = padded(fit_model_rest_vertices(body), nv);
    float(*to)[4] = padded(posed, nv);
    float(*x)[4] = padded(m->xyz, m->num_vertices);
    int32_t(*tris)[4] = malloc((size_t)nt * sizeof *tris);
    sim_carry *c = sim_carry_create(nv);
    int r = -1;
    if (from && to && x && tris && c) {
        const int32_t *t = fit_model_triangles(body);
        for (int i = 0; i < nt; i++)
            for (int k = 0; k < 4; k++)
                tris[i][k] = k < 3 ? t[i * 3 + k] : 0;
        r = sim_carry_between(c, (const float(*)[4])from, (const float(*)[4])to,
                              (const int32_t(*)[4])tris, nv, nt, x, m->num_vertices);
        for (int i = 0; r == 0 && i < m->num_vertices; i++)
            for (int k = 0; k < 3; k++)
                m->xyz[i * 3 + k] = x[i][k];
    }
    if (r < 0)
        sim_reject_set(why, SIM_ERR_NO_MEMORY, "carrying the dressed garment to the body's pose");
    sim_carry_destroy(c);
    free(from);
    free(to);
    free(x);
    free(tris);
    return r < 0 ? -SIM_ERR_NO_MEMORY : 0;
}

/* The panels meshed at the spacing that gives about target vertices (0: gar_mesh_build's
 * default, 2 cm): a mesh's vertex count goes about as its area over the spacing squared, so
 * one mesh at the default and one correction from it, then one more from that (the outline's
 * share of the vertices does not scale the same way). */
static int mesh_to(const gar_pattern *p, int target, gar_mesh *m, float *spacing_m, gar_reject *gw)
{
    gar_mesh_desc md = {.spacing_m = SIM_PATTERN_DEFAULT_SPACING_M};
    int r = gar_mesh_build(p, &md, m, gw);
    for (int pass = 0; r == 0 && target > 0 && pass < 2; pass++) {
        float good = md.spacing_m, h = good * sqrtf((float)m->num_vertices / (float)target);
        if (fabsf(h - good) < 0.01f * good)
            break;
        md.spacing_m = h;
        gar_mesh_free(m);
        if (gar_mesh_build(p, &md, m, gw) == 0)
            continue;
        /* a target the mesher cannot reach (a spacing out of its range, too many points): the
           last mesh it made */
        md.spacing_m = good;
        r = gar_mesh_build(p, &md, m, gw);
        break;
    }
    *spacing_m = md.spacing_m;
    return r;
}

/* The pattern read, graded, meshed, placed and dressed on the model at rest. */
static int dress(const sim_outfit *o, const fit_model *body, int target, gar_mesh *m,
                 sim_pattern_stats *st, int8_t **part_of, sim_reject *why)
{
    gar_pattern p = {0};
    gar_reject gw = {0};
    gar_dress_stats ds = {0};
    int r = gar_pattern_load(o->garment, &p, &gw);
    if (r == 0) {
        gar_pattern_grade(&p, (gar_size)o->size);
        r = mesh_to(&p, target, m, &st->spacing_m, &gw);
    }
    if (r == 0)
        r = gar_mesh_place(&p, m, body, NULL, NULL, NULL, &gw);
    if (r < 0) {
        gar_pattern_free(&p);
        return sim_reject_set(why, SIM_ERR_FILE, "pattern %.80s: %s: %.100s", o->garment,
                              gar_error_name(r), gw.detail);
    }
    /* Without the dressing's spreading rounds: they move a corner's stretch along its edge for
       tryon-bench-dress's settled figure, but the moving body's settle does that here, and the
       T-shirt dressed with them walked at 5.2 % strain against 2.0 % without (test_sim_pattern,
       1,109 vertices; docs/garments.md, "The T-shirt with the arms lowered") */
    gar_dress_desc d = {.fabric = gar_fabric_find(o->fabric_name), .spread_rounds = -1};
    r = gar_dress_tryon(&p, m, body, &d, &ds, &gw);
    if (r == 0 && part_of && !(*part_of = malloc((size_t)m->num_vertices)))
        r = -GAR_ERR_NO_MEMORY;
    for (int i = 0; r == 0 && part_of && i < m->num_vertices; i++)
        (*part_of)[i] = (int8_t)gar_panel_part(&p, m->panel_of[i]);
    gar_pattern_free(&p);
    if (r < 0)
        return sim_reject_set(why, SIM_ERR_FILE, "pattern %.80s: dressing: %s: %.100s", o->garment,
                              gar_error_name(r), gw.detail);
    st->dress_ms = ds.ms;
    st->seam_gap_mm = ds.seam_gap_mm;
    st->penetrating = ds.penetrating;
    st->max_strain = ds.max_strain;
    st->p99_strain = ds.p99_strain;
    return 0;
}

int sim_pattern_dress_on(const sim_outfit *o, const fit_model *body, const float *posed_xyz,
                         int target_vertices, sim_garment *out, int8_t **part_of,
                         sim_pattern_stats *stats, sim_reject *why)
{
    double t0 = now_ms();
    sim_pattern_stats st = {0};
    if (part_of)
        *part_of = NULL;
    if (!o || !o->is_pattern || !out || !body || !posed_xyz || target_vertices < 0)
        return sim_reject_set(why, SIM_ERR_ARG, "not a pattern outfit, a body and its pose");
    gar_mesh m = {0};
    int r = dress(o, body, target_vertices, &m, &st, part_of, why);
    if (r == 0)
        r = carry_to(body, posed_xyz, &m, why);
    if (r == 0 && (r = sim_pattern_weld(&m, out, part_of ? *part_of : NULL, why)) == 0) {
        snprintf(out->id, sizeof out->id, "%.63s", o->id);
        r = sim_pattern_hold(out, posed_xyz, fit_model_vertex_count(body),
                             fit_model_triangles(body), fit_model_triangle_count(body), why);
        r = r < 0 ? r : 0;
        if (r < 0)
            sim_garment_free(out);
    }
    gar_mesh_free(&m);
    if (r < 0 && part_of) {
        free(*part_of);
        *part_of = NULL;
    }
    st.total_ms = (float)(now_ms() - t0);
    if (stats)
        *stats = st;
    return r;
}

int sim_outfit_make_pattern(const sim_outfit *o, const float *shape, int num_shape,
                            const float *pose, int num_pose, const float *body_xyz, int nv,
                            const int32_t *body_tris, int nt, int target_vertices, sim_garment *out,
                            sim_pattern_stats *stats, sim_reject *why)
{
    double t0 = now_ms();
    char err[200] = "";
    if (!o || !o->is_pattern || !out)
        return sim_reject_set(why, SIM_ERR_ARG, "not a pattern outfit");
    if (!shape || num_shape != FIT_SHAPE_PARAMS || !pose || num_pose != FIT_POSE_PARAMS)
        return sim_reject_set(why, SIM_ERR_PARAM,
                              "body has %d shape and %d pose values, the body model's %d and %d "
                              "needed to dress a pattern",
                              num_shape, num_pose, FIT_SHAPE_PARAMS, FIT_POSE_PARAMS);
    fit_shape s = fit_shape_from_array(shape);
    if (fit_shape_validate(&s, err, sizeof err) != 0)
        return sim_reject_set(why, SIM_ERR_PARAM, "body shape: %.150s", err);
    fit_pose fp;
    memcpy(fp.root, pose, sizeof fp.root);
    memcpy(fp.rot, pose + 3, sizeof fp.rot);
    for (int i = 0; i < FIT_POSE_PARAMS; i++)
        if (!isfinite(pose[i]))
            return sim_reject_set(why, SIM_ERR_NOT_FINITE, "body pose value %d", i);
    fit_model *body = fit_model_create(&(fit_model_desc){.shape = s}, err, sizeof err);
    if (!body)
        return sim_reject_set(why, SIM_ERR_PARAM, "body model: %.150s", err);
    float *posed = malloc((size_t)fit_model_vertex_count(body) * 3 * sizeof *posed);
    float joints[FIT_JOINT_COUNT * 3];
    int r = posed && fit_model_pose(body, &fp, posed, joints) == 0
                ? sim_pattern_dress_on(o, body, posed, target_vertices, out, NULL, stats, why)
                : sim_reject_set(why, SIM_ERR_NO_MEMORY, "posing the body model");
    /* the attachments moved from the model's mesh to the body's (same shape and pose) */
    if (r == 0 && body_xyz &&
        (r = sim_garment_rebind(out, posed, fit_model_vertex_count(body), fit_model_triangles(body),
                                fit_model_triangle_count(body), body_xyz, nv, body_tris, nt, why)) <
            0)
        sim_garment_free(out);
    free(posed);
    fit_model_destroy(body);
    if (stats)
        stats->total_ms = (float)(now_ms() - t0);
    return r;
}

int sim_pattern_settle(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                       sim_reject *why)
{
    int r = 0;
    /* part of dressing, done once before the garment is worn: whole, whatever a live stage's
       frame budget (sim_desc.frame_budget_ms) */
    float budget_ms = s->desc.frame_budget_ms;
    s->desc.frame_budget_ms = 0.0f;
    for (int k = 0; k < SIM_PATTERN_SETTLE_FRAMES && r == 0; k++) {
        sim_frame_stats st;
        r = sim_step(s, body_xyz, nv, body_tris, nt, &st, why);
    }
    s->desc.frame_budget_ms = budget_ms;
    return r;
}

float sim_pattern_thickness_m(void)
{
    return GAR_TRYON_THICKNESS_M;
}
