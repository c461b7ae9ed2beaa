/* The body as an implicit surface: an exponential smooth union of a lofted elliptical torso,
 * an ellipsoid head and tapered capsules along the limbs. The same per-primitive distances give
 * the skinning weights (a soft partition of the surface among the bones). */
#include "body_internal.h"

#include <math.h>

#define FIT_PI 3.14159265358979f

static void cone_init(body_cone *c, const float a[3], const float b[3], float ra, float rb,
                      int joint)
{
    float l2 = 0.0f;
    for (int k = 0; k < 3; ++k) {
        c->a[k] = a[k];
        c->ba[k] = b[k] - a[k];
        l2 += c->ba[k] * c->ba[k];
        c->split_dir[k] = 0.0f;
    }
    c->inv_l2 = l2 > 0.0f ? 1.0f / l2 : 0.0f;
    c->ra = ra;
    c->rb = rb;
    c->joint = joint;
    c->joint2 = -1;
    c->split_lo = 0.0f;
    c->split_hi = 1.0f;
}

static body_cone *add_cone(body_field *f, const float a[3], const float b[3], float ra, float rb,
                           int joint)
{
    body_cone *c = &f->cone[f->cone_count++];
    cone_init(c, a, b, ra, rb, joint);
    return c;
}

static void along(const float a[3], const float d[3], float t, float out[3])
{
    for (int k = 0; k < 3; ++k)
        out[k] = a[k] + t * d[k];
}

static void build_arm(body_field *f, const body_skeleton *sk, const fit_shape *s,
                      const body_calib *c, int side)
{
    float sc = sk->scale, r = c->arm * s->arm_girth / (2.0f * FIT_PI);
    int cl = side == 0 ? FIT_L_CLAVICLE : FIT_R_CLAVICLE;
    const float *sh = sk->joint[cl + 1], *el = sk->joint[cl + 2], *wr = sk->joint[cl + 3];
    float hand[3];
    along(wr, sk->arm_dir[side], 0.10f * sc, hand);
    add_cone(f, sk->joint[cl], sh, 0.048f * sc, 1.02f * r, cl);
    add_cone(f, sh, el, 1.08f * r, 0.76f * r, cl + 1);
    /* Wrists and hands keep a floor: a thin upper arm does not make a needle of a hand. */
    float rw = fmaxf(0.52f * r, 0.022f * sc), rh = fmaxf(0.50f * r, 0.021f * sc);
    add_cone(f, el, wr, 0.74f * r, rw, cl + 2);
    add_cone(f, wr, hand, fmaxf(0.56f * r, rw), rh, cl + 3);
}

static void build_leg(body_field *f, const body_skeleton *sk, const fit_shape *s,
                      const body_calib *c, int side)
{
    float sc = sk->scale, r = c->leg * s->leg_girth / (2.0f * FIT_PI);
    int hip = side == 0 ? FIT_L_HIP : FIT_R_HIP;
    const float *hp = sk->joint[hip], *kn = sk->joint[hip + 1], *an = sk->joint[hip + 2];
    const float *toe = sk->joint[hip + 3];
    /* The thigh starts below the hip joint so its top stays inside the hip outline. */
    float top[3];
    for (int k = 0; k < 3; ++k)
        top[k] = hp[k] + 0.15f * (kn[k] - hp[k]);
    add_cone(f, top, kn, 1.0f * r, 0.62f * r, hip);
    add_cone(f, kn, an, 0.60f * r, fmaxf(0.40f * r, 0.03f * sc), hip + 1);
    float heel[3] = {an[0], an[1] - 0.035f * sc, an[2] - 0.045f * sc};
    float tip[3] = {an[0], 0.028f * sc, toe[2] + 0.06f * sc};
    body_cone *foot = add_cone(f, heel, tip, 0.038f * sc, 0.028f * sc, hip + 2);
    foot->joint2 = hip + 3;
    foot->split_dir[2] = 1.0f;
    foot->split_lo = toe[2] - 0.03f * sc;
    foot->split_hi = toe[2] + 0.02f * sc;
}

/* Torso keyframes bottom to top: below the hips, hips, waist, chest, shoulders. Girth-named
 * sections get semi-axes from the girth through Ramanujan's perimeter, times the calibration. */
static void build_torso(body_field *f, const body_skeleton *sk, const fit_shape *s,
                        const body_calib *c)
{
    float sc = sk->scale;
    float ah = c->hip * s->hip_girth / (FIT_PI * body_ellipse_g(BODY_HIP_Q));
    float aw = c->waist * s->waist_girth / (FIT_PI * body_ellipse_g(BODY_WAIST_Q));
    float ac = c->chest * s->chest_girth / (FIT_PI * body_ellipse_g(BODY_CHEST_Q));
    float top = sk->joint[FIT_L_SHOULDER][1] + 0.01f * sc;
    const float y[BODY_TORSO_KEYS] = {sk->hip_y - 0.08f * sc, sk->hip_y, sk->waist_y, sk->chest_y,
                                      top};
    const float a[BODY_TORSO_KEYS] = {0.86f * ah, ah, aw, ac, 0.42f * s->shoulder_width};
    const float b[BODY_TORSO_KEYS] = {0.86f * BODY_HIP_Q * ah, BODY_HIP_Q * ah, BODY_WAIST_Q * aw,
                                      BODY_CHEST_Q * ac, 0.62f * ac};
    const float z[BODY_TORSO_KEYS] = {-0.02f * sc, -0.015f * sc, 0.0f, 0.01f * sc, -0.01f * sc};
    for (int i = 0; i < BODY_TORSO_KEYS; ++i) {
        f->key_y[i] = y[i];
        f->key_a[i] = a[i];
        f->key_b[i] = b[i];
        f->key_z[i] = z[i];
    }
    f->torso_lo = y[0];
    f->torso_hi = top;
    f->torso_round = 0.035f * sc;
    f->torso_round_top = 0.07f * sc; /* slopes the shoulders into the neck */
    f->spine_y = sk->joint[FIT_SPINE][1];
    f->chest_y = sk->joint[FIT_CHEST][1];
    f->torso_ramp = 0.05f * sc;
}

void body_field_build(const body_skeleton *sk, const fit_shape *s, const body_calib *c,
                      body_field *f)
{
    float sc = sk->scale;
    f->cone_count = 0;
    build_torso(f, sk, s, c);
    f->head_c[0] = 0.0f;
    f->head_c[1] = s->height - 0.115f * sc;
    f->head_c[2] = 0.01f * sc;
    f->head_r[0] = 0.075f * sc;
    f->head_r[1] = 0.115f * sc;
    f->head_r[2] = 0.095f * sc;
    float nb[3] = {0.0f, sk->joint[FIT_L_SHOULDER][1] - 0.02f * sc, -0.01f * sc};
    float nt[3] = {0.0f, s->height - 0.16f * sc, 0.0f};
    add_cone(f, nb, nt, 0.058f * sc, 0.052f * sc, FIT_NECK);
    for (int side = 0; side < 2; ++side) {
        build_arm(f, sk, s, c, side);
        build_leg(f, sk, s, c, side);
    }
    f->min_radius = 1.0f;
    for (int i = 0; i < f->cone_count; ++i)
        f->min_radius = fminf(f->min_radius, fminf(f->cone[i].ra, f->cone[i].rb));
    f->blend = 0.010f * sc;
    f->skin_sigma = 0.010f * sc;
    /* Bounds: every joint and the head, padded by the largest radius and a margin. */
    for (int k = 0; k < 3; ++k) {
        f->lo[k] = f->head_c[k] - f->head_r[k];
        f->hi[k] = f->head_c[k] + f->head_r[k];
    }
    for (int i = 0; i < f->cone_count; ++i) {
        const body_cone *cn = &f->cone[i];
        float r = (cn->ra > cn->rb ? cn->ra : cn->rb) + 0.05f;
        for (int k = 0; k < 3; ++k) {
            float e0 = cn->a[k], e1 = cn->a[k] + cn->ba[k];
            float mn = e0 < e1 ? e0 : e1, mx = e0 < e1 ? e1 : e0;
            f->lo[k] = fminf(f->lo[k], mn - r);
            f->hi[k] = fmaxf(f->hi[k], mx + r);
        }
    }
    for (int i = 0; i < BODY_TORSO_KEYS; ++i) {
        f->lo[0] = fminf(f->lo[0], -f->key_a[i] - 0.05f);
        f->hi[0] = fmaxf(f->hi[0], f->key_a[i] + 0.05f);
        f->lo[2] = fminf(f->lo[2], f->key_z[i] - f->key_b[i] - 0.05f);
        f->hi[2] = fmaxf(f->hi[2], f->key_z[i] + f->key_b[i] + 0.05f);
    }
    f->lo[1] = fmaxf(f->lo[1], -0.05f);
    f->hi[1] = fmaxf(f->hi[1], s->height + 0.05f);
    for (int i = 0; i < f->cone_count; ++i) {
        const body_cone *cn = &f->cone[i];
        f->soa.ax[i] = cn->a[0], f->soa.ay[i] = cn->a[1], f->soa.az[i] = cn->a[2];
        f->soa.bx[i] = cn->ba[0], f->soa.by[i] = cn->ba[1], f->soa.bz[i] = cn->ba[2];
        f->soa.inv_l2[i] = cn->inv_l2, f->soa.ra[i] = cn->ra, f->soa.rb[i] = cn->rb;
    }
}

/* Distance to each cone (a tapered capsule: to the segment, minus the radius there), d[i] for
 * cone i. Written over the arrays of f->soa so that it vectorises: four cones at a time, the
 * same operations on each (field.c is built with -fno-math-errno and -fno-trapping-math, see
 * CMakeLists.txt; the body's models stay the same to the bit). */
static void cone_dists(const body_field *f, const float p[3], float *restrict d)
{
    const float *ax = f->soa.ax, *ay = f->soa.ay, *az = f->soa.az;
    const float *bx = f->soa.bx, *by = f->soa.by, *bz = f->soa.bz;
    const float *il = f->soa.inv_l2, *ra = f->soa.ra, *rb = f->soa.rb;
    for (int i = 0, n = f->cone_count; i < n; ++i) {
        float pa0 = p[0] - ax[i], pa1 = p[1] - ay[i], pa2 = p[2] - az[i];
        float t = (pa0 * bx[i] + pa1 * by[i] + pa2 * bz[i]) * il[i];
        t = t < 0.0f ? 0.0f : t; /* two plain selects: a nested one does not vectorise */
        t = t > 1.0f ? 1.0f : t;
        float d0 = pa0 - t * bx[i], d1 = pa1 - t * by[i], d2 = pa2 - t * bz[i];
        d[i] = sqrtf(d0 * d0 + d1 * d1 + d2 * d2) - (ra[i] + t * (rb[i] - ra[i]));
    }
}

/* Near-surface distance to an ellipse / ellipsoid: k0 (k0 - 1) / k1 with k0 = |p / r| and
 * k1 = |p / r^2|; exact on the surface, a bound away from it. */
static float ellipse_dist(float x, float z, float a, float b)
{
    float k0 = sqrtf((x / a) * (x / a) + (z / b) * (z / b));
    float k1 = sqrtf((x / (a * a)) * (x / (a * a)) + (z / (b * b)) * (z / (b * b)));
    return k1 > 1e-12f ? k0 * (k0 - 1.0f) / k1 : -fminf(a, b);
}

static float ellipsoid_dist(const float c[3], const float r[3], const float p[3])
{
    float q[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    float k0 = 0.0f, k1 = 0.0f;
    for (int k = 0; k < 3; ++k) {
        k0 += (q[k] / r[k]) * (q[k] / r[k]);
        k1 += (q[k] / (r[k] * r[k])) * (q[k] / (r[k] * r[k]));
    }
    k0 = sqrtf(k0);
    k1 = sqrtf(k1);
    return k1 > 1e-12f ? k0 * (k0 - 1.0f) / k1 : -fminf(r[0], fminf(r[1], r[2]));
}

/* Section at height y: smoothstep between keyframes, so each named section is a plateau. */
static void torso_section(const body_field *f, float y, float *a, float *b, float *z)
{
    int i = 0;
    while (i < BODY_TORSO_KEYS - 2 && y > f->key_y[i + 1])
        ++i;
    float t = body_smoothstep(f->key_y[i], f->key_y[i + 1], y);
    *a = f->key_a[i] + t * (f->key_a[i + 1] - f->key_a[i]);
    *b = f->key_b[i] + t * (f->key_b[i + 1] - f->key_b[i]);
    *z = f->key_z[i] + t * (f->key_z[i + 1] - f->key_z[i]);
}

/* Elliptical loft cut by two planes; the rims are rounded by offsetting inward and back out. */
static float torso_dist(const body_field *f, const float p[3])
{
    /* Either rim's radius applies only near its own cut, so switching halfway is seamless. */
    float mid = 0.5f * (f->torso_lo + f->torso_hi);
    float a, b, z, r = p[1] > mid ? f->torso_round_top : f->torso_round;
    torso_section(f, p[1], &a, &b, &z);
    float de = ellipse_dist(p[0], p[2] - z, a, b) + r;
    float dc = body_maxf(f->torso_lo - p[1], p[1] - f->torso_hi) + r;
    float d = (de > 0.0f && dc > 0.0f) ? sqrtf(de * de + dc * dc) : body_maxf(de, dc);
    return d - r;
}

/* Distances to every primitive: [0] torso, [1] head, [2 + i] cone i. Returns the count. */
static int prim_dists(const body_field *f, const float p[3], float *d)
{
    d[0] = torso_dist(f, p);
    d[1] = ellipsoid_dist(f->head_c, f->head_r, p);
    cone_dists(f, p, d + 2);
    return 2 + f->cone_count;
}

float body_field_prim_dist(const body_field *f, int prim, const float p[3])
{
    if (prim == 0)
        return torso_dist(f, p);
    if (prim == 1)
        return ellipsoid_dist(f->head_c, f->head_r, p);
    const body_cone *c = &f->cone[prim - 2];
    float pa[3] = {p[0] - c->a[0], p[1] - c->a[1], p[2] - c->a[2]};
    float t = body_dot(pa, c->ba) * c->inv_l2;
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    float d[3] = {pa[0] - t * c->ba[0], pa[1] - t * c->ba[1], pa[2] - t * c->ba[2]};
    return sqrtf(body_dot(d, d)) - (c->ra + t * (c->rb - c->ra));
}

/* Exponential smooth union -k ln sum exp(-d_i / k), shifted by the minimum for range. */
float body_field_eval(const body_field *f, const float p[3])
{
    float d[BODY_MAX_PRIMS];
    int n = prim_dists(f, p, d);
    float mn = d[0];
    for (int i = 1; i < n; ++i)
        mn = body_minf(mn, d[i]);
    float k = f->blend, sum = 0.0f;
    for (int i = 0; i < n; ++i) {
        float e = (d[i] - mn) / k;
        if (e < 12.0f)
            sum += expf(-e);
    }
    return mn - k * logf(sum);
}

void body_field_grad(const body_field *f, const float p[3], float g[3])
{
    const float h = 1e-4f;
    for (int k = 0; k < 3; ++k) {
        float a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
        a[k] += h;
        b[k] -= h;
        g[k] = (body_field_eval(f, a) - body_field_eval(f, b)) / (2.0f * h);
    }
}

/* Forward differences from a known value v: half the evaluations of body_field_grad. */
static void grad_forward(const body_field *f, const float p[3], float v, float g[3])
{
    const float h = 1e-4f;
    for (int k = 0; k < 3; ++k) {
        float a[3] = {p[0], p[1], p[2]};
        a[k] += h;
        g[k] = (body_field_eval(f, a) - v) / h;
    }
}

void body_field_project(const body_field *f, float p[3])
{
    float v = body_field_eval(f, p);
    for (int it = 0; it < 4 && fabsf(v) > 1e-6f; ++it) {
        float g[3];
        grad_forward(f, p, v, g);
        float g2 = body_dot(g, g);
        if (g2 < 1e-12f)
            return;
        for (int k = 0; k < 3; ++k)
            p[k] -= v * g[k] / g2;
        v = body_field_eval(f, p);
    }
}

static void torso_weights(const body_field *f, float y, float share, float *w)
{
    float up = body_smoothstep(f->spine_y - f->torso_ramp, f->spine_y + f->torso_ramp, y);
    float ch = body_smoothstep(f->chest_y - f->torso_ramp, f->chest_y + f->torso_ramp, y);
    w[FIT_PELVIS] += share * (1.0f - up);
    w[FIT_SPINE] += share * (up - ch);
    w[FIT_CHEST] += share * ch;
}

void body_field_joint_weights(const body_field *f, const float p[3], float w[FIT_JOINT_COUNT])
{
    float d[BODY_MAX_PRIMS], s[BODY_MAX_PRIMS];
    int n = prim_dists(f, p, d);
    float mn = d[0], sum = 0.0f;
    for (int i = 1; i < n; ++i)
        mn = body_minf(mn, d[i]);
    for (int i = 0; i < n; ++i) {
        float e = (d[i] - mn) / f->skin_sigma;
        s[i] = e < 20.0f ? expf(-e) : 0.0f;
        sum += s[i];
    }
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        w[j] = 0.0f;
    torso_weights(f, p[1], s[0] / sum, w);
    w[FIT_HEAD] += s[1] / sum;
    for (int i = 0; i < f->cone_count; ++i) {
        const body_cone *c = &f->cone[i];
        float share = s[2 + i] / sum, t2 = 0.0f;
        if (c->joint2 >= 0) {
            t2 = body_smoothstep(c->split_lo, c->split_hi, body_dot(p, c->split_dir));
            w[c->joint2] += share * t2;
        }
        w[c->joint] += share * (1.0f - t2);
    }
}
