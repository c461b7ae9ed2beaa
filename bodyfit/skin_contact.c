/* The contact pass after linear blend skinning: where two parts of the posed body pass through
 * each other (an upper arm lowered into the chest, a raised thigh into the belly), each part's
 * skin stops at their contact surface instead of going through. This is the contact step of
 * implicit skinning (Vaillant et al. 2013, "Implicit Skinning", sec. 4.3), on the model's own
 * implicit primitives (field.c) carried rigidly by their joints: the contact surface between
 * parts A and B is where their distances are equal, d_B(p) = d_A(p); a vertex of A found inside
 * B is moved by Newton steps on h = d_B - d_A to h = CONTACT_GAP_M, a vertex of B inside A to
 * d_A - d_B = CONTACT_GAP_M. Parts: the trunk (pelvis, spine, chest, neck, head), each arm
 * (clavicle down), each leg (hip down); a vertex belongs to the part holding most of its
 * skinning weight. At rest no vertex lies inside a primitive (the smooth union is below each
 * primitive's distance), so the rest pose is unchanged. */
#include "body_internal.h"

#include <math.h>

enum { PART_TRUNK, PART_L_ARM, PART_R_ARM, PART_L_LEG, PART_R_LEG, PART_COUNT };

/* The two sheets of skin at a contact are kept 6 mm apart: coplanar sheets would leave the
   inside of the body ambiguous to the sim's collider and to a ray test, and the mesh's edges
   (about 2 cm at 6,000 vertices) join moved vertices to unmoved ones across the gap. Measured
   (test_bodyfit_contact, vertices > 2 mm inside another part, arms_down held / boxing_guard):
   3 mm 15 / -, 6 mm 9 / 29, 10 mm 8 / 33. */
#define CONTACT_GAP_M 0.006f
/* A vertex is only moved once 0.1 mm inside another part: rest vertices lie on the surface to
   Newton's 1e-6 and the decimation's projection, so this keeps the rest pose exact. */
#define CONTACT_TRIGGER_M 1e-4f
/* At most this far a vertex is moved, m: deeper than any overlap the joint limits allow
   (measured: 29 mm at the armpit), so only a failed Newton step is clipped. */
#define CONTACT_MAX_PUSH_M 0.06f
/* Only a vertex holding at least this share of its weight in its part is moved: where a
   joint's weights blend parts (the groin between pelvis and both thighs, the armpit's apex)
   moving single vertices by a part's distances tore triangles (measured at 69 degrees of hip
   flexion: 45 mm moves, a groin triangle stretched 11x; with 0.7, 4.6x as plain skinning does;
   0.6 and 0.8 gave the same counts inside, test_bodyfit_contact). */
#define CONTACT_SHARE 0.7f
/* Newton stops within this of CONTACT_GAP_M, m: usually after one step, the distances being
   near linear over a few centimetres */
#define CONTACT_TOL_M        5e-4f
#define CONTACT_NEWTON_STEPS 3
#define CONTACT_FD_M         1e-4f /* forward-difference step for the gradient of h, m */

typedef struct contact {
    const body_field *f;
    float inv[FIT_JOINT_COUNT][12]; /* the field's rest <- posed: rows [R^T | -R^T t], then the
                                       model's unshape map where it was reshaped */
    float offset[FIT_JOINT_COUNT];  /* m, the girth the reshaping gave the joint's part */
    int n[PART_COUNT];
    short prim[PART_COUNT][BODY_MAX_PRIMS], joint[PART_COUNT][BODY_MAX_PRIMS];
} contact;

/* The shoulder girdle goes with its arm: the clavicle's cone caps the shoulder joint, and a
 * raised arm's skin sweeping through it is the shoulder's own bend, not a contact (measured on
 * the trunk's side: moves of 60 mm at 69 degrees of abduction, triangles squashed to 1 %). */
static int joint_part(int j)
{
    if (j >= FIT_L_CLAVICLE && j <= FIT_L_WRIST)
        return PART_L_ARM;
    if (j >= FIT_R_CLAVICLE && j <= FIT_R_WRIST)
        return PART_R_ARM;
    if (j >= FIT_L_HIP && j <= FIT_L_TOE)
        return PART_L_LEG;
    if (j >= FIT_R_HIP && j <= FIT_R_TOE)
        return PART_R_LEG;
    return PART_TRUNK;
}

/* The part holding most of vertex i's weight, and (share) that weight. */
static int vertex_part(const fit_model *m, int i, float *share)
{
    float w[PART_COUNT] = {0};
    for (int k = 0; k < FIT_MAX_INFLUENCES; ++k)
        w[joint_part(m->wjoint[(size_t)i * FIT_MAX_INFLUENCES + k])] +=
            m->weight[(size_t)i * FIT_MAX_INFLUENCES + k];
    int best = 0;
    for (int a = 1; a < PART_COUNT; ++a)
        if (w[a] > w[best])
            best = a;
    *share = w[best];
    return best;
}

static void add_prim(contact *c, int part, int prim, int joint)
{
    c->prim[part][c->n[part]] = (short)prim;
    c->joint[part][c->n[part]++] = (short)joint;
}

static void contact_init(contact *c, const fit_model *m, const float skin[][12])
{
    c->f = &m->field;
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        const float *s = skin[j];
        for (int r = 0; r < 3; ++r) {
            float *o = c->inv[j] + r * 4;
            o[0] = s[r], o[1] = s[4 + r], o[2] = s[8 + r];
            o[3] = -(o[0] * s[3] + o[1] * s[7] + o[2] * s[11]);
        }
        c->offset[j] = 0.0f;
        if (m->reshaped) {
            const float *u = m->unshape[j];
            float x[12];
            for (int r = 0; r < 3; ++r)
                for (int k = 0; k < 4; ++k)
                    x[r * 4 + k] = u[r * 4] * c->inv[j][k] + u[r * 4 + 1] * c->inv[j][4 + k] +
                                   u[r * 4 + 2] * c->inv[j][8 + k] + (k == 3 ? u[r * 4 + 3] : 0.0f);
            for (int k = 0; k < 12; ++k)
                c->inv[j][k] = x[k];
            c->offset[j] = m->unshape_offset[j];
        }
    }
    for (int a = 0; a < PART_COUNT; ++a)
        c->n[a] = 0;
    add_prim(c, PART_TRUNK, 0, FIT_PELVIS); /* the torso: its three bands, see part_dist */
    add_prim(c, PART_TRUNK, 1, FIT_HEAD);
    for (int i = 0; i < m->field.cone_count; ++i) {
        int j = m->field.cone[i].joint;
        add_prim(c, joint_part(j), 2 + i, j);
    }
}

static void to_rest(const float x[12], const float p[3], float q[3])
{
    for (int r = 0; r < 3; ++r)
        q[r] = x[r * 4] * p[0] + x[r * 4 + 1] * p[1] + x[r * 4 + 2] * p[2] + x[r * 4 + 3];
}

/* The torso is skinned to pelvis, spine and chest by height (field.c, torso_weights): each
 * joint carries its own band of the rest torso, and outside its band a copy is as far as the
 * band's edge, so a bent trunk is not doubled by copies of the other bands. */
static float torso_posed_dist(const contact *c, const float p[3])
{
    const float lo[3] = {-INFINITY, c->f->spine_y, c->f->chest_y};
    const float hi[3] = {c->f->spine_y, c->f->chest_y, INFINITY};
    const int joint[3] = {FIT_PELVIS, FIT_SPINE, FIT_CHEST};
    float q[3][3], band[3];
    for (int b = 0; b < 3; ++b) {
        to_rest(c->inv[joint[b]], p, q[b]);
        band[b] = body_maxf(lo[b] - q[b][1], q[b][1] - hi[b]);
    }
    /* the point's own band first (band <= 0); another band's copy only where its edge is nearer
       than what is found (the loft is the costly part) */
    int first = band[0] <= 0.0f ? 0 : (band[1] <= 0.0f ? 1 : 2);
    float d = body_maxf(body_field_prim_dist(c->f, 0, q[first]), band[first]);
    for (int b = 0; b < 3; ++b)
        if (b != first && band[b] < d)
            d = body_minf(d, body_maxf(body_field_prim_dist(c->f, 0, q[b]), band[b]));
    return d;
}

/* Distance from a posed point to part a: its primitives, each carried by its joint. */
static float part_dist(const contact *c, int a, const float p[3])
{
    float d = INFINITY;
    for (int k = 0; k < c->n[a]; ++k) {
        if (c->prim[a][k] == 0) {
            d = body_minf(d, torso_posed_dist(c, p));
            continue;
        }
        float q[3];
        int j = c->joint[a][k];
        to_rest(c->inv[j], p, q);
        d = body_minf(d, body_field_prim_dist(c->f, c->prim[a][k], q) - c->offset[j]);
    }
    return d;
}

/* How far p lies on a's side of the contact surface of parts a and b, m (> 0: a's side). */
static float contact_h(const contact *c, int a, int b, const float p[3])
{
    return part_dist(c, b, p) - part_dist(c, a, p);
}

/* Moves p, a vertex of part a inside part b, to contact_h = CONTACT_GAP_M by Newton steps
 * along the gradient of contact_h (forward differences). */
static void resolve(const contact *c, int a, int b, float p[3])
{
    float p0[3] = {p[0], p[1], p[2]};
    for (int it = 0; it < CONTACT_NEWTON_STEPS; ++it) {
        float h = contact_h(c, a, b, p);
        if (h >= CONTACT_GAP_M - CONTACT_TOL_M)
            break;
        float g[3];
        for (int k = 0; k < 3; ++k) {
            float q[3] = {p[0], p[1], p[2]};
            q[k] += CONTACT_FD_M;
            g[k] = (contact_h(c, a, b, q) - h) / CONTACT_FD_M;
        }
        float g2 = body_dot(g, g);
        if (!(g2 > 1e-6f))
            break;
        float s = (CONTACT_GAP_M - h) / g2;
        for (int k = 0; k < 3; ++k)
            p[k] += s * g[k];
    }
    float d[3] = {p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]};
    float l = sqrtf(body_dot(d, d));
    if (l > CONTACT_MAX_PUSH_M)
        for (int k = 0; k < 3; ++k)
            p[k] = p0[k] + d[k] * (CONTACT_MAX_PUSH_M / l);
}

static int in_box(const float lo[3], const float hi[3], const float p[3])
{
    return p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] &&
           p[2] <= hi[2];
}

/* Whether vertex i, at p, is to be moved out of part b: inside b and outside b at rest. A model
 * reshaped after it was built (the tracker's learnt shape, fit_shape_base_apply) measures the
 * primitives of its first shape through its unshape maps, which the blend of a joint's
 * vertices follows only nearly; where its rest skin still pokes into them that is the
 * reshaping, not a contact: the rest pose stays as it is. */
static int in_contact(const contact *c, const contact *rest, const fit_model *m, int i, int b,
                      const float p[3])
{
    return part_dist(c, b, p) < -CONTACT_TRIGGER_M &&
           part_dist(rest, b, m->mesh.v + (size_t)i * 3) >= 0.0f;
}

void body_skin_contact(const fit_model *m, const float skin[][12], float *vertices)
{
    static const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    float rest_skin[FIT_JOINT_COUNT][12];
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        for (int k = 0; k < 12; ++k)
            rest_skin[j][k] = identity[k];
    contact c, rest;
    contact_init(&c, m, skin);
    contact_init(&rest, m, (const float(*)[12])rest_skin);
    /* Each part's posed bounds: a vertex far from a part's box cannot be inside it. */
    float lo[PART_COUNT][3], hi[PART_COUNT][3];
    for (int a = 0; a < PART_COUNT; ++a)
        for (int k = 0; k < 3; ++k)
            lo[a][k] = INFINITY, hi[a][k] = -INFINITY;
    int nv = m->mesh.nv;
    for (int i = 0; i < nv; ++i) {
        float share;
        int a = vertex_part(m, i, &share);
        const float *p = vertices + (size_t)i * 3;
        for (int k = 0; k < 3; ++k)
            lo[a][k] = body_minf(lo[a][k], p[k]), hi[a][k] = body_maxf(hi[a][k], p[k]);
    }
    for (int i = 0; i < nv; ++i) {
        float share;
        int a = vertex_part(m, i, &share);
        float *p = vertices + (size_t)i * 3;
        for (int b = 0; b < PART_COUNT && share >= CONTACT_SHARE; ++b)
            if (b != a && in_box(lo[b], hi[b], p) && in_contact(&c, &rest, m, i, b, p))
                resolve(&c, a, b, p);
    }
}
