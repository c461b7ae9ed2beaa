/* Placement around tryon's body: each panel wrapped on a surface of revolution around the body
 * part it belongs to (torso, an arm, a leg; axes from the body's joints), at its own height,
 * facing the way the file faces it, a clearance outside the body's widest point at each level.
 * Arc length along u is kept, so a panel is placed unstretched. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodyfit.h"
#include "pattern_internal.h"
#include "place_internal.h"

#define GAR_DEFAULT_CLEARANCE_M 0.02f
/* The shipped files are drawn for bodyfit's average body (1.75 m) and its torso slices' heights
 * (fit_model_measure: hip, waist, chest; test_garment_waist checks them against the model). A
 * file's heights are mapped piecewise linearly through these to the actual body's, so that what
 * the file puts at the reference waist lands at this body's waist: scaling by height alone put
 * a skirt's waistband 10 cm under the slim tall body's waist (docs/garments.md, "Placement"). */
#define GAR_REFERENCE_HEIGHT_M 1.75f
#define GAR_REFERENCE_HIP_Y    0.937f
#define GAR_REFERENCE_WAIST_Y  1.095f
#define GAR_REFERENCE_CHEST_Y  1.254f
#define GAR_HEIGHT_KNOTS       5
/* Radius profiles in 1 cm bins along each part's axis. */
#define GAR_PROFILE_BIN_M 0.01f
#define GAR_PROFILE_BINS  256
/* Radius change per metre along the axis at most (about 17 degrees). */
#define GAR_PROFILE_SLOPE 0.3f
/* Panel classes from the file placement (reference body, metres): arms hang outside 0.25 m
 * above 1.0 m, legs are panels off the centre line below 0.85 m. */
#define GAR_ARM_MIN_X 0.25f
#define GAR_ARM_MIN_Y 1.0f
#define GAR_LEG_MIN_X 0.03f
#define GAR_LEG_MAX_Y 0.85f

static void sub3(const float *a, const float *b, float *o)
{
    o[0] = a[0] - b[0], o[1] = a[1] - b[1], o[2] = a[2] - b[2];
}
static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static void cross3(const float *a, const float *b, float *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static void norm3(float *a)
{
    float l = sqrtf(dot3(a, a));
    if (l > 0)
        a[0] /= l, a[1] /= l, a[2] /= l;
}

gar_part gar_panel_part(const gar_pattern *p, int panel)
{
    const gar_panel *pn = &p->panels[panel];
    float c[2] = {0, 0}, w[3];
    for (int v = 0; v < pn->num_vertices; v++)
        c[0] += pn->uv_m[2 * v] / pn->num_vertices, c[1] += pn->uv_m[2 * v + 1] / pn->num_vertices;
    gar_panel_to_world(pn, c, w);
    if (fabsf(w[0]) > GAR_ARM_MIN_X && w[1] > GAR_ARM_MIN_Y)
        return w[0] > 0 ? GAR_PART_ARM_L : GAR_PART_ARM_R;
    if (fabsf(w[0]) > GAR_LEG_MIN_X && w[1] < GAR_LEG_MAX_Y)
        return w[0] > 0 ? GAR_PART_LEG_L : GAR_PART_LEG_R;
    return GAR_PART_TORSO;
}

/* The body's part a vertex belongs to, from its strongest skinning joint. Torso vertices count
 * for a leg on that leg's side of the pelvis (a waistband wraps the hip). */
static int vertex_in_part(gar_part part, int joint, float x, float pelvis_x)
{
    int arm_l = joint == FIT_L_SHOULDER || joint == FIT_L_ELBOW || joint == FIT_L_WRIST;
    int arm_r = joint == FIT_R_SHOULDER || joint == FIT_R_ELBOW || joint == FIT_R_WRIST;
    /* The feet stay out: a hem hangs over them and the push-out step clears them. */
    int leg_l = joint >= FIT_L_HIP && joint <= FIT_L_ANKLE;
    int leg_r = joint >= FIT_R_HIP && joint <= FIT_R_ANKLE;
    if (joint == FIT_L_TOE || joint == FIT_R_TOE)
        return 0;
    int torso = !arm_l && !arm_r && !leg_l && !leg_r && joint != FIT_HEAD;
    switch (part) {
    case GAR_PART_ARM_L:
        return arm_l;
    case GAR_PART_ARM_R:
        return arm_r;
    case GAR_PART_LEG_L:
        return leg_l || (torso && x >= pelvis_x);
    case GAR_PART_LEG_R:
        return leg_r || (torso && x <= pelvis_x);
    case GAR_PART_TORSO:
    default:
        return torso || leg_l || leg_r;
    }
}

/* A part's axis: vertical parts use height for s and a vertical line through the axis point;
 * arms use distance from the shoulder along the shoulder-wrist line. */
typedef struct part_axis {
    int vertical;
    float top[3], bottom[3], dir[3]; /* dir: unit top -> bottom */
    float length;
    float radius[GAR_PROFILE_BINS];
} part_axis;

static void axis_point(const part_axis *ax, float s, float out[3])
{
    if (ax->vertical) { /* s = height: interpolate between the joints, clamped */
        float t = (ax->top[1] - s) / (ax->top[1] - ax->bottom[1]);
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        for (int k = 0; k < 3; k++)
            out[k] = ax->top[k] + t * (ax->bottom[k] - ax->top[k]);
        out[1] = s;
        return;
    }
    for (int k = 0; k < 3; k++)
        out[k] = ax->top[k] + s * ax->dir[k];
}

/* s of a point and its distance from the axis. */
static void axis_coords(const part_axis *ax, const float *p, float *s, float *r)
{
    float a[3], d[3];
    if (ax->vertical) {
        *s = p[1];
        axis_point(ax, p[1], a);
        *r = hypotf(p[0] - a[0], p[2] - a[2]);
        return;
    }
    sub3(p, ax->top, d);
    *s = dot3(d, ax->dir);
    axis_point(ax, *s, a);
    sub3(p, a, d);
    *r = sqrtf(dot3(d, d));
}

static int bin_of(const part_axis *ax, float s)
{
    float base = ax->vertical ? 0.0f : -0.5f; /* arms: half a metre above the shoulder */
    int b = (int)floorf((s - base) / GAR_PROFILE_BIN_M);
    return b < 0 ? 0 : b >= GAR_PROFILE_BINS ? GAR_PROFILE_BINS - 1 : b;
}

static void build_axis(gar_part part, const float *joints, const fit_model *body, const float *xyz,
                       part_axis *ax)
{
    static const int ends[GAR_PART_COUNT][2] = {{FIT_PELVIS, FIT_PELVIS},
                                                {FIT_L_SHOULDER, FIT_L_WRIST},
                                                {FIT_R_SHOULDER, FIT_R_WRIST},
                                                {FIT_L_HIP, FIT_L_ANKLE},
                                                {FIT_R_HIP, FIT_R_ANKLE}};
    memset(ax, 0, sizeof *ax);
    ax->vertical = part == GAR_PART_TORSO || part == GAR_PART_LEG_L || part == GAR_PART_LEG_R;
    memcpy(ax->top, joints + 3 * ends[part][0], sizeof ax->top);
    memcpy(ax->bottom, joints + 3 * ends[part][1], sizeof ax->bottom);
    if (part == GAR_PART_TORSO)
        ax->top[1] += 1, ax->bottom[1] -= 1; /* a vertical line through the pelvis */
    sub3(ax->bottom, ax->top, ax->dir);
    ax->length = sqrtf(dot3(ax->dir, ax->dir));
    norm3(ax->dir);
    int nv = fit_model_vertex_count(body);
    const uint8_t *wj = fit_model_weight_joints(body);
    const float *ww = fit_model_weights(body);
    float pelvis_x = joints[3 * FIT_PELVIS];
    for (int v = 0; v < nv; v++) {
        int best = 0;
        for (int k = 1; k < FIT_MAX_INFLUENCES; k++)
            if (ww[4 * v + k] > ww[4 * v + best])
                best = k;
        if (!vertex_in_part(part, wj[4 * v + best], xyz[3 * v], pelvis_x))
            continue;
        float s, r;
        axis_coords(ax, xyz + 3 * v, &s, &r);
        int b = bin_of(ax, s);
        ax->radius[b] = fmaxf(ax->radius[b], r);
    }
    /* The profile dilated by a cone of slope GAR_PROFILE_SLOPE: it clears every slice and
     * changes gently from row to row, so a panel's rows stay close to their rest spacing. */
    float r[GAR_PROFILE_BINS];
    for (int i = 0; i < GAR_PROFILE_BINS; i++) {
        r[i] = 0;
        for (int k = 0; k < GAR_PROFILE_BINS; k++)
            r[i] = fmaxf(r[i], ax->radius[k] - GAR_PROFILE_SLOPE * GAR_PROFILE_BIN_M * abs(i - k));
    }
    memcpy(ax->radius, r, sizeof r);
}

/* Radius at s: the widest body slice within two bins, so neighbouring rows see the same body. */
static float radius_at(const part_axis *ax, float s)
{
    int b = bin_of(ax, s);
    float r = 0;
    for (int k = b - 2; k <= b + 2; k++)
        if (k >= 0 && k < GAR_PROFILE_BINS)
            r = fmaxf(r, ax->radius[k]);
    return r;
}

/* The file's facing of a panel and the u at which it faces the axis. */
static void panel_frame(const gar_panel *pn, const part_axis *ax, int torso, float hs, float *e1,
                        float *uc)
{
    float o[2] = {0, 0}, ux[2] = {1, 0}, vy[2] = {0, 1}, w0[3], wu[3], wv[3], n[3], du[3], dv[3];
    gar_panel_to_world(pn, o, w0);
    gar_panel_to_world(pn, ux, wu);
    gar_panel_to_world(pn, vy, wv);
    sub3(wu, w0, du);
    sub3(wv, w0, dv);
    cross3(du, dv, n);
    float lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < pn->num_vertices; v++)
        lo = fminf(lo, pn->uv_m[2 * v]), hi = fmaxf(hi, pn->uv_m[2 * v]);
    if (ax->vertical) { /* facing: the file normal made horizontal */
        e1[0] = n[0], e1[1] = 0, e1[2] = n[2];
        norm3(e1);
        if (!torso) { /* a leg panel centred on its leg */
            *uc = (lo + hi) / 2;
            return;
        }
        float a[3]; /* a torso panel keeps the file's centring on the body's axis */
        axis_point(ax, w0[1] * hs, a);
        *uc = (a[0] - w0[0] * hs) * du[0] + (a[2] - w0[2] * hs) * du[2];
        return;
    }
    /* A sleeve wraps the limb around the file's facing, centred in u: a one-piece sleeve facing
       front wraps it all from the front, the halves of a two-piece one (the data sets' front
       and back sleeve panels) each their own side. */
    float nd = dot3(n, ax->dir);
    for (int k = 0; k < 3; k++)
        e1[k] = n[k] - nd * ax->dir[k];
    if (!(dot3(e1, e1) > 1e-12f)) { /* a panel facing along the limb: from the front */
        float z[3] = {0, 0, 1}, zd = dot3(z, ax->dir);
        for (int k = 0; k < 3; k++)
            e1[k] = z[k] - zd * ax->dir[k];
    }
    norm3(e1);
    *uc = (lo + hi) / 2;
}

/* A limb panel's direction up the limb, towards the shoulder, in its own (u, v): towards its
 * edges stitched to torso panels (the sleeve's cap), snapped to the nearest of +-u and +-v (the
 * data sets' sleeves run along u, tryon's along v); +v when none is stitched to the torso. */
static void limb_up(const gar_pattern *p, int pi, float up[2])
{
    const gar_panel *pn = &p->panels[pi];
    float c[2] = {0, 0}, m[2] = {0, 0};
    int n = 0;
    for (int v = 0; v < pn->num_vertices; v++)
        c[0] += pn->uv_m[2 * v] / pn->num_vertices, c[1] += pn->uv_m[2 * v + 1] / pn->num_vertices;
    for (int s = 0; s < p->num_stitches; s++)
        for (int k = 0; k < 2; k++) {
            if (p->stitches[s].panel[k] != pi ||
                gar_panel_part(p, p->stitches[s].panel[1 - k]) != GAR_PART_TORSO)
                continue;
            float mid[2];
            gar_edge_eval(pn, &pn->edges[p->stitches[s].edge[k]], 0.5f, mid);
            m[0] += mid[0], m[1] += mid[1], n++;
        }
    up[0] = 0, up[1] = 1;
    if (n == 0)
        return;
    float d[2] = {m[0] / n - c[0], m[1] / n - c[1]};
    if (fabsf(d[0]) > fabsf(d[1]))
        up[0] = d[0] > 0 ? 1.0f : -1.0f, up[1] = 0;
    else
        up[1] = d[1] < 0 ? -1.0f : 1.0f;
}

/* The reference body's landmark heights (floor, hip, waist, chest, top) and this body's. */
typedef struct height_map {
    float ref[GAR_HEIGHT_KNOTS], body[GAR_HEIGHT_KNOTS];
} height_map;

static int height_map_make_scaled(float height, height_map *hm)
{
    const float ref[GAR_HEIGHT_KNOTS] = {0, GAR_REFERENCE_HIP_Y, GAR_REFERENCE_WAIST_Y,
                                         GAR_REFERENCE_CHEST_Y, GAR_REFERENCE_HEIGHT_M};
    for (int k = 0; k < GAR_HEIGHT_KNOTS; k++)
        hm->ref[k] = ref[k], hm->body[k] = ref[k] * height / GAR_REFERENCE_HEIGHT_M;
    return 0;
}

static int height_map_make(const fit_model *body, height_map *hm)
{
    fit_measurements ms;
    if (fit_model_measure(body, &ms) < 0)
        return -1;
    float h = fit_model_shape(body)->height;
    const float ref[GAR_HEIGHT_KNOTS] = {0, GAR_REFERENCE_HIP_Y, GAR_REFERENCE_WAIST_Y,
                                         GAR_REFERENCE_CHEST_Y, GAR_REFERENCE_HEIGHT_M};
    const float mine[GAR_HEIGHT_KNOTS] = {0, ms.hip_y, ms.waist_y, ms.chest_y, h};
    for (int k = 1; k < GAR_HEIGHT_KNOTS; k++)
        if (!(mine[k] > mine[k - 1])) /* not in order: scale by height alone */
            return height_map_make_scaled(h, hm);
    memcpy(hm->ref, ref, sizeof ref);
    memcpy(hm->body, mine, sizeof mine);
    return 0;
}

/* y on the reference body -> the same place on this body (linear past the last knots). */
static float height_map_apply(const height_map *hm, float y)
{
    int k = 1;
    while (k < GAR_HEIGHT_KNOTS - 1 && y > hm->ref[k])
        k++;
    float t = (y - hm->ref[k - 1]) / (hm->ref[k] - hm->ref[k - 1]);
    return hm->body[k - 1] + t * (hm->body[k] - hm->body[k - 1]);
}

int gar_mesh_place(const gar_pattern *p, gar_mesh *m, const fit_model *body, const float *body_xyz,
                   const float *joints, const gar_place_desc *desc, gar_reject *why)
{
    if (!p || !m || !body || m->num_panels != p->num_panels)
        return gar_refuse(why, GAR_ERR_ARG, "placement needs a pattern, its mesh and a body");
    const float *xyz = body_xyz ? body_xyz : fit_model_rest_vertices(body);
    const float *jn = joints ? joints : fit_model_rest_joints(body);
    float clear = desc && desc->clearance_m > 0 ? desc->clearance_m : GAR_DEFAULT_CLEARANCE_M;
    float hs = fit_model_shape(body)->height / GAR_REFERENCE_HEIGHT_M;
    height_map hm;
    if (height_map_make(body, &hm) < 0)
        return gar_refuse(why, GAR_ERR_ARG, "placement: the body's torso cannot be measured");
    part_axis *ax = malloc(sizeof *ax);
    if (!ax)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "placement");
    for (int pi = 0; pi < p->num_panels; pi++) {
        const gar_panel *pn = &p->panels[pi];
        gar_part part = gar_panel_part(p, pi);
        build_axis(part, jn, body, xyz, ax);
        float e1[3], e2[3], tv[3], uc, vmax = -INFINITY, up[2] = {0, 1};
        panel_frame(pn, ax, part == GAR_PART_TORSO, hs, e1, &uc);
        if (!ax->vertical) { /* a sleeve: (u, v) turned in its plane so that +v runs up the limb */
            limb_up(p, pi, up);
            float lo = INFINITY, hi = -INFINITY;
            for (int v = 0; v < pn->num_vertices; v++) {
                const float *q = pn->uv_m + 2 * v;
                float u1 = q[0] * up[1] - q[1] * up[0];
                lo = fminf(lo, u1), hi = fmaxf(hi, u1);
            }
            uc = (lo + hi) / 2;
        }
        for (int v = 0; v < pn->num_vertices; v++)
            vmax = fmaxf(vmax, pn->uv_m[2 * v] * up[0] + pn->uv_m[2 * v + 1] * up[1]);
        /* +v runs up the body, or up the limb towards the shoulder; e2 = tv x e1 makes +u
         * turn so that the panel's front normal (u x v) points away from the axis. */
        if (ax->vertical)
            tv[0] = 0, tv[1] = 1, tv[2] = 0;
        else
            tv[0] = -ax->dir[0], tv[1] = -ax->dir[1], tv[2] = -ax->dir[2];
        cross3(tv, e1, e2);
        for (int v = 0; v < m->num_vertices; v++) {
            if (m->panel_of[v] != pi)
                continue;
            const float *uv = m->uv_m + 2 * v;
            float s, w[3], a[3];
            if (ax->vertical) {
                gar_panel_to_world(pn, uv, w);
                s = height_map_apply(&hm, w[1]);
            } else { /* the cap's top at the shoulder joint */
                s = (vmax - (uv[0] * up[0] + uv[1] * up[1])) * hs;
            }
            axis_point(ax, s, a);
            float u1 = ax->vertical ? uv[0] : uv[0] * up[1] - uv[1] * up[0];
            float r = radius_at(ax, s) + clear, phi = (u1 - uc) / r;
            for (int k = 0; k < 3; k++)
                m->xyz[3 * v + k] = a[k] + r * (cosf(phi) * e1[k] + sinf(phi) * e2[k]);
        }
    }
    free(ax);
    int rc = gar_push_out(body, xyz, m->xyz, m->num_vertices, clear);
    return rc ? gar_refuse(why, -rc, "pushing the placed garment out of the body") : 0;
}
