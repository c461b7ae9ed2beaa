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

/* The dressed mesh moved with the model from rest to pose (sim/carry.c: each point with the
 * body vertex nearest it, turned as that vertex's triangle turned). */
static int carry_to_pose(const fit_model *body, const fit_pose *pose, gar_mesh *m, sim_reject *why)
{
    int nv = fit_model_vertex_count(body), nt = fit_model_triangle_count(body);
    float *posed = malloc((size_t)nv * 3 * sizeof *posed);
    float joints[FIT_JOINT_COUNT * 3];
    float(*from)[4] = padded(fit_model_rest_vertices(body), nv);
    float(*x)[4] = padded(m->xyz, m->num_vertices);
    int32_t(*tris)[4] = malloc((size_t)nt * sizeof *tris);
    sim_carry *c = sim_carry_create(nv);
    float(*to)[4] = NULL;
    int r = -1;
    if (posed && from && x && tris && c && fit_model_pose(body, pose, posed, joints) == 0 &&
        (to = padded(posed, nv))) {
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
    free(posed);
    free(from);
    free(to);
    free(x);
    free(tris);
    return r < 0 ? -SIM_ERR_NO_MEMORY : 0;
}

/* The pattern read, graded, meshed, placed and dressed on the model at rest. */
static int dress(const sim_outfit *o, const fit_model *body, gar_mesh *m, sim_pattern_stats *st,
                 sim_reject *why)
{
    gar_pattern p = {0};
    gar_reject gw = {0};
    gar_dress_stats ds = {0};
    int r = gar_pattern_load(o->garment, &p, &gw);
    if (r == 0) {
        gar_pattern_grade(&p, (gar_size)o->size);
        r = gar_mesh_build(&p, NULL, m, &gw);
    }
    if (r == 0)
        r = gar_mesh_place(&p, m, body, NULL, NULL, NULL, &gw);
    if (r < 0) {
        gar_pattern_free(&p);
        return sim_reject_set(why, SIM_ERR_FILE, "pattern %.80s: %s: %.100s", o->garment,
                              gar_error_name(r), gw.detail);
    }
    gar_dress_desc d = {.fabric = gar_fabric_find(o->fabric_name)};
    r = gar_dress_tryon(&p, m, body, &d, &ds, &gw);
    gar_pattern_free(&p);
    if (r < 0)
        return sim_reject_set(why, SIM_ERR_FILE, "pattern %.80s: dressing: %s: %.100s", o->garment,
                              gar_error_name(r), gw.detail);
    st->dress_ms = ds.ms;
    st->seam_gap_mm = ds.seam_gap_mm;
    st->penetrating = ds.penetrating;
    return 0;
}

/* The garment the sim gets: positions and triangles; masses lumped from the fabric's density. */
static int to_sim_garment(const sim_outfit *o, const gar_mesh *m, sim_garment *out, sim_reject *why)
{
    memset(out, 0, sizeof *out);
    out->xyz = malloc((size_t)m->num_vertices * 3 * sizeof *out->xyz);
    out->triangles = malloc((size_t)m->num_triangles * 3 * sizeof *out->triangles);
    if (!out->xyz || !out->triangles) {
        sim_garment_free(out);
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "garment of %d vertices", m->num_vertices);
    }
    memcpy(out->xyz, m->xyz, (size_t)m->num_vertices * 3 * sizeof *out->xyz);
    memcpy(out->triangles, m->triangles, (size_t)m->num_triangles * 3 * sizeof *out->triangles);
    out->num_vertices = m->num_vertices;
    out->num_triangles = m->num_triangles;
    snprintf(out->id, sizeof out->id, "%.63s", o->id);
    return 0;
}

int sim_outfit_make_pattern(const sim_outfit *o, const float *shape, int num_shape,
                            const float *pose, int num_pose, sim_garment *out,
                            sim_pattern_stats *stats, sim_reject *why)
{
    double t0 = now_ms();
    sim_pattern_stats st = {0};
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
    gar_mesh m = {0};
    int r = dress(o, body, &m, &st, why);
    if (r == 0)
        r = carry_to_pose(body, &fp, &m, why);
    if (r == 0)
        r = to_sim_garment(o, &m, out, why);
    gar_mesh_free(&m);
    fit_model_destroy(body);
    st.total_ms = (float)(now_ms() - t0);
    if (stats)
        *stats = st;
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
