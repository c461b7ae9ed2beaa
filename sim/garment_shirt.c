/* A shirt generated around a body mesh: a tube over the torso from the armpits to the hips,
 * following the torso's radial profile offset outward, its top row attached to the body (so it
 * hangs from the chest as a shirt hangs from the shoulders). The arms stay outside it: under each
 * arm the top edge dips into an armhole (docs/sim.md, "Garments"), so that an arm lowered to the
 * side hangs beside the cloth, not through its glued top row. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "collide_geometry.h"

#define SHIRT_PI               3.14159265358979f
#define SHIRT_DEFAULT_OFFSET_M 0.015f /* a fitted shirt stands 1.5 cm off the skin */
#define SHIRT_DEFAULT_HEM_M    0.12f  /* the hem at the hips, 12 cm below the pelvis joint */
#define SHIRT_MIN_VERTICES     200
#define SHIRT_MAX_VERTICES     200000
/* The armhole: under each arm the top edge is this much lower than at the chest and back. With
 * the arms lowered to 6 degrees from vertical (bench body) the arm's inner surface comes within
 * 6 mm of the torso at the tube's former top (shoulder joint - 0.25 m) and 11 mm 5 cm lower,
 * nearer than the shirt stands off the skin; 8 cm lower it is 27 mm away (docs/sim-history.md,
 * "Arms down: the cause"). */
#define SHIRT_ARMHOLE_M 0.08f
/* Half-width of the armhole around the shoulder's direction seen from the torso axis, radians:
 * an upper arm is about 10 cm across on a torso of about 15 cm radius (+-20 deg), with margin. */
#define SHIRT_ARMHOLE_HALF 0.6f

/* bodyfit joint indices (bodyfit.h FIT_JOINT_LIST order); the sim does not link bodyfit for
 * this, it only reads the joint array a body message carries. */
enum { J_PELVIS = 0, J_NECK = 3, J_LSHO = 6, J_LELB = 7, J_LWRI = 8, J_RSHO = 10 };
enum { J_RELB = 11, J_RWRI = 12 };

typedef struct shirt_frame {
    float axis[2]; /* x, z of the torso's vertical axis */
    float y_top, y_bot;
    float arm_th[2]; /* the tube's angle of each shoulder joint (with joints) */
    float armhole_m; /* how much lower the top edge is under the arms; 0 without joints */
} shirt_frame;

/* Torso vertices: nearer the pelvis-neck segment than any arm bone (with joints), or inside the
 * middle 60 % of the body's width (without). The tube's top (armpits) and hem (hem_m below the
 * pelvis joint) into f. */
static void classify(const float *xyz, int nv, const float *j, float hem_m, uint8_t *torso,
                     shirt_frame *f)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < nv; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fminf(lo[d], xyz[i * 3 + d]);
            hi[d] = fmaxf(hi[d], xyz[i * 3 + d]);
        }
    float cx = 0.5f * (lo[0] + hi[0]), half = 0.5f * (hi[0] - lo[0]);
    for (int i = 0; i < nv; i++) {
        const float *p = &xyz[i * 3];
        if (!j) {
            torso[i] = fabsf(p[0] - cx) < 0.6f * half;
            continue;
        }
        float dt = sim_segment_dist2(p, &j[J_PELVIS * 3], &j[J_NECK * 3]);
        /* the legs count as torso: a long hem (a tunic) encloses the tops of the thighs */
        static const int bones[][2] = {
            {J_LSHO, J_LELB}, {J_LELB, J_LWRI}, {J_RSHO, J_RELB}, {J_RELB, J_RWRI}};
        torso[i] = 1;
        for (int b = 0; b < 4; b++)
            if (sim_segment_dist2(p, &j[bones[b][0] * 3], &j[bones[b][1] * 3]) < dt)
                torso[i] = 0;
    }
    float ylo = INFINITY, yhi = -INFINITY, sx = 0, sz = 0;
    int n = 0;
    for (int i = 0; i < nv; i++) {
        if (!torso[i])
            continue;
        ylo = fminf(ylo, xyz[i * 3 + 1]);
        yhi = fmaxf(yhi, xyz[i * 3 + 1]);
        sx += xyz[i * 3];
        sz += xyz[i * 3 + 2];
        n++;
    }
    f->axis[0] = n ? sx / (float)n : cx;
    f->axis[1] = n ? sz / (float)n : 0.5f * (lo[2] + hi[2]);
    if (j) {
        /* armpits sit about 8 cm below the shoulder joints */
        f->y_top = fminf(j[J_LSHO * 3 + 1], j[J_RSHO * 3 + 1]) - 0.25f;
        f->y_bot = j[J_PELVIS * 3 + 1] - hem_m;
        static const int sho[2] = {J_LSHO, J_RSHO};
        for (int k = 0; k < 2; k++)
            f->arm_th[k] = atan2f(-(j[sho[k] * 3 + 2] - f->axis[1]), j[sho[k] * 3] - f->axis[0]);
        f->armhole_m = SHIRT_ARMHOLE_M;
    } else {
        f->y_top = yhi - 0.25f * (yhi - ylo);
        f->y_bot = ylo + 0.2f * (yhi - ylo);
        f->armhole_m = 0.0f;
    }
}

/* The top edge's height at tube angle th: y_top, lower by up to armhole_m under each arm (a
 * cos^2 bump of half-width SHIRT_ARMHOLE_HALF, smooth so the glued row has no corner). */
static float top_at(const shirt_frame *f, float th)
{
    float dip = 0.0f;
    for (int k = 0; k < 2; k++) {
        float d = remainderf(th - f->arm_th[k], 2.0f * SHIRT_PI);
        if (fabsf(d) < SHIRT_ARMHOLE_HALF) {
            float c = cosf(0.5f * SHIRT_PI * d / SHIRT_ARMHOLE_HALF);
            dip = fmaxf(dip, c * c);
        }
    }
    return f->y_top - f->armhole_m * dip;
}

/* Largest radius of the torso in each (row, column) bin, then dilated so that the tube clears
 * the body between bin centres too. */
static void radial_profile(const float *xyz, int nv, const uint8_t *torso, const shirt_frame *f,
                           int rows, int cols, float *r)
{
    float *raw = calloc((size_t)rows * cols, sizeof *raw);
    float dy = (f->y_top - f->y_bot) / (float)(rows - 1);
    for (int i = 0; raw && i < nv; i++) {
        if (!torso[i])
            continue;
        const float *p = &xyz[i * 3];
        int row = (int)lroundf((f->y_top - p[1]) / dy);
        if (row < -1 || row > rows)
            continue;
        row = row < 0 ? 0 : (row >= rows ? rows - 1 : row);
        float x = p[0] - f->axis[0], z = p[2] - f->axis[1];
        float th = atan2f(-z, x); /* the tube's angle runs clockwise seen from above */
        int col = (int)lroundf(th / (2.0f * SHIRT_PI) * (float)cols);
        col = ((col % cols) + cols) % cols;
        raw[row * cols + col] = fmaxf(raw[row * cols + col], sqrtf(x * x + z * z));
    }
    float rmax = 0.0f;
    for (int k = 0; raw && k < rows * cols; k++)
        rmax = fmaxf(rmax, raw[k]);
    int reach = cols / 24 + 1; /* about 15 degrees either side */
    for (int i = 0; i < rows; i++) {
        for (int c = 0; c < cols; c++) {
            float m = 0.0f;
            for (int di = -1; raw && di <= 1; di++)
                for (int dc = -reach; dc <= reach; dc++) {
                    int ii = i + di, cc = ((c + dc) % cols + cols) % cols;
                    if (ii >= 0 && ii < rows)
                        m = fmaxf(m, raw[ii * cols + cc]);
                }
            r[i * cols + c] = m > 0.0f ? m : rmax;
        }
    }
    /* below the waist the cloth falls straight from the widest point of the hips: a hem that
     * narrows under the buttocks would hang stretched */
    for (int i = rows / 2; i < rows; i++)
        for (int c = 0; c < cols; c++)
            r[i * cols + c] = fmaxf(r[i * cols + c], r[(i - 1) * cols + c]);
    free(raw);
}

/* Vertex p glued to body triangle t, exactly on its plane: the barycentrics of p's projection
 * (possibly a little outside the triangle) plus the height along its unit normal, so that the
 * attachment reproduces p. */
static void glue(const float *p, const float *xyz, const int32_t *tris, int t, sim_attachment *at)
{
    const int32_t *v = &tris[t * 3];
    const float *a = &xyz[v[0] * 3], *b = &xyz[v[1] * 3], *q = &xyz[v[2] * 3];
    float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float e2[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
    float ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                  e1[0] * e2[1] - e1[1] * e2[0]};
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++)
        n[k] /= len;
    float h = ap[0] * n[0] + ap[1] * n[1] + ap[2] * n[2];
    float w[3] = {ap[0] - h * n[0], ap[1] - h * n[1], ap[2] - h * n[2]};
    float d00 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    float d01 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    float d11 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    float d20 = w[0] * e1[0] + w[1] * e1[1] + w[2] * e1[2];
    float d21 = w[0] * e2[0] + w[1] * e2[1] + w[2] * e2[2];
    float den = d00 * d11 - d01 * d01;
    float b1 = (d11 * d20 - d01 * d21) / den, b2 = (d00 * d21 - d01 * d20) / den;
    at->body_triangle = t;
    at->bary[0] = 1.0f - b1 - b2;
    at->bary[1] = b1;
    at->bary[2] = b2;
    at->offset_m = h;
}

/* Each triangle's bounding sphere (centre, radius a little padded against rounding), so that the
 * nearest-triangle scans below skip triangles that cannot be nearer than the best so far: the
 * shirt's glue and a rebind scan the whole body once per column, which took tens of ms. */
typedef struct tri_spheres {
    float (*c)[4]; /* x, y, z, radius */
} tri_spheres;

static int tri_spheres_make(tri_spheres *s, const float *xyz, const int32_t *tris, int nt)
{
    s->c = malloc((size_t)(nt > 0 ? nt : 1) * sizeof *s->c);
    if (!s->c)
        return -1;
    for (int t = 0; t < nt; t++) {
        const int32_t *v = &tris[t * 3];
        float r2 = 0.0f;
        for (int k = 0; k < 3; k++)
            s->c[t][k] = (xyz[v[0] * 3 + k] + xyz[v[1] * 3 + k] + xyz[v[2] * 3 + k]) / 3.0f;
        for (int i = 0; i < 3; i++) {
            const float *q = &xyz[v[i] * 3];
            float d2 = (q[0] - s->c[t][0]) * (q[0] - s->c[t][0]) +
                       (q[1] - s->c[t][1]) * (q[1] - s->c[t][1]) +
                       (q[2] - s->c[t][2]) * (q[2] - s->c[t][2]);
            r2 = fmaxf(r2, d2);
        }
        s->c[t][3] = sqrtf(r2) * 1.0001f + 1e-6f;
    }
    return 0;
}

/* The triangle nearest p among those whose vertices are all in mask (NULL: all); -1 if none. */
static int nearest_triangle(const float *p, const float *xyz, const int32_t *tris, int nt,
                            const uint8_t *mask, const tri_spheres *s)
{
    float best = INFINITY, best_d = INFINITY; /* squared, and its root */
    int bt = -1;
    for (int t = 0; t < nt; t++) {
        const int32_t *v = &tris[t * 3];
        if (mask && (!mask[v[0]] || !mask[v[1]] || !mask[v[2]]))
            continue;
        const float *sc = s->c[t];
        float dc2 = (p[0] - sc[0]) * (p[0] - sc[0]) + (p[1] - sc[1]) * (p[1] - sc[1]) +
                    (p[2] - sc[2]) * (p[2] - sc[2]);
        float reach = best_d + sc[3];
        if (dc2 > reach * reach)
            continue; /* the whole triangle is farther than the best (no root taken a triangle) */
        float q[3], bary[3];
        sim_closest_on_triangle(p, &xyz[v[0] * 3], &xyz[v[1] * 3], &xyz[v[2] * 3], q, bary);
        float d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                   (p[2] - q[2]) * (p[2] - q[2]);
        if (d2 < best) {
            best = d2;
            best_d = sqrtf(d2);
            bt = t;
        }
    }
    return bt;
}

/* The top row hangs from the body: each vertex of the columns outside the armholes (top_at =
 * y_top) glued to its nearest torso triangle. The armholes' edge hangs free, as a sleeveless
 * top's does: glued, neighbours on its slope sit at heights where the skinning blends pelvis
 * and spine differently, and twisting the trunk moved them 43 % apart (docs/sim-history.md, "Arms
 * down: the cause"). Returns the number of attachments, or a negative error. */
static int attach_top_row(sim_garment *g, int cols, const shirt_frame *f, const float *xyz,
                          const int32_t *tris, int nt, const uint8_t *torso, sim_reject *why)
{
    tri_spheres s;
    if (tri_spheres_make(&s, xyz, tris, nt) < 0)
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "shirt: %d triangles", nt);
    int na = 0;
    for (int c = 0; c < cols; c++) {
        if (top_at(f, 2.0f * SHIRT_PI * (float)c / (float)cols) < f->y_top)
            continue;
        int bt = nearest_triangle(&g->xyz[c * 3], xyz, tris, nt, torso, &s);
        if (bt < 0) {
            free(s.c);
            return sim_reject_set(why, SIM_ERR_PARAM, "shirt: no torso triangle near column %d", c);
        }
        g->attachments[na].vertex = c;
        glue(&g->xyz[c * 3], xyz, tris, bt, &g->attachments[na++]);
    }
    free(s.c);
    g->num_attachments = na;
    return na;
}

int sim_garment_rebind(sim_garment *g, const float *from_xyz, int from_nv, const int32_t *from_tris,
                       int from_nt, const float *to_xyz, int to_nv, const int32_t *to_tris,
                       int to_nt, sim_reject *why)
{
    int r = sim_body_validate(from_xyz, from_nv, from_tris, from_nt, why);
    if (r == 0)
        r = sim_body_validate(to_xyz, to_nv, to_tris, to_nt, why);
    if (r == 0)
        r = sim_garment_validate(g, from_nt, why);
    if (r < 0)
        return r;
    tri_spheres s;
    if (tri_spheres_make(&s, to_xyz, to_tris, to_nt) < 0)
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "rebind: %d triangles", to_nt);
    for (int a = 0; a < g->num_attachments; a++) {
        sim_attachment *at = &g->attachments[a];
        const int32_t *v = &from_tris[at->body_triangle * 3];
        float foot[3];
        for (int k = 0; k < 3; k++)
            foot[k] = at->bary[0] * from_xyz[v[0] * 3 + k] + at->bary[1] * from_xyz[v[1] * 3 + k] +
                      at->bary[2] * from_xyz[v[2] * 3 + k];
        int t = nearest_triangle(foot, to_xyz, to_tris, to_nt, NULL, &s);
        if (t < 0) {
            free(s.c);
            return sim_reject_set(why, SIM_ERR_PARAM, "rebind: no triangle near attachment %d", a);
        }
        glue(&g->xyz[at->vertex * 3], to_xyz, to_tris, t, at);
    }
    free(s.c);
    return 0;
}

int sim_garment_shirt(const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                      const float *joints_xyz, int n_vertices, float offset_m, float hem_m,
                      sim_garment *out, sim_reject *why)
{
    int r = sim_body_validate(body_xyz, nv, body_tris, nt, why);
    if (r < 0)
        return r;
    if (!out || n_vertices < SHIRT_MIN_VERTICES || n_vertices > SHIRT_MAX_VERTICES ||
        !(offset_m >= 0.0f && offset_m < 0.2f) || !(hem_m >= 0.0f && hem_m < 0.5f))
        return sim_reject_set(
            why, SIM_ERR_PARAM,
            "shirt: %d vertices (%d..%d), offset %g m (0..0.2), hem %g m (0..0.5)", n_vertices,
            SHIRT_MIN_VERTICES, SHIRT_MAX_VERTICES, offset_m, hem_m);
    offset_m = offset_m > 0.0f ? offset_m : SHIRT_DEFAULT_OFFSET_M;
    hem_m = hem_m > 0.0f ? hem_m : SHIRT_DEFAULT_HEM_M;
    uint8_t *torso = calloc((size_t)nv, 1);
    if (!torso)
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "shirt");
    shirt_frame f;
    classify(body_xyz, nv, joints_xyz, hem_m, torso, &f);
    /* square cells: columns around a perimeter of about 2 pi 0.15 m, rows down the height */
    float height = f.y_top - f.y_bot, perim = 2.0f * SHIRT_PI * 0.15f;
    if (!(height > 0.05f)) {
        free(torso);
        return sim_reject_set(why, SIM_ERR_PARAM, "shirt: torso height %g m", height);
    }
    float h = sqrtf(perim * height / (float)n_vertices);
    int cols = (int)lroundf(perim / h), rows = (int)lroundf(height / h) + 1;
    cols = cols < 8 ? 8 : cols;
    rows = rows < 3 ? 3 : rows;
    r = sim_garment_alloc(out, rows * cols, 2 * cols * (rows - 1), cols);
    float *rad = malloc((size_t)rows * cols * sizeof *rad);
    if (r < 0 || !rad) {
        free(torso);
        free(rad);
        sim_garment_free(out);
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "shirt of %d vertices", rows * cols);
    }
    radial_profile(body_xyz, nv, torso, &f, rows, cols, rad);
    for (int i = 0; i < rows; i++) {
        for (int c = 0; c < cols; c++) {
            /* each column from its own top (the armholes) down to the hem; the radius is the
               profile's at that height */
            float th = 2.0f * SHIRT_PI * (float)c / (float)cols, top = top_at(&f, th);
            float y = top - (top - f.y_bot) * (float)i / (float)(rows - 1);
            int row = (int)lroundf((f.y_top - y) / height * (float)(rows - 1));
            row = row < 0 ? 0 : (row >= rows ? rows - 1 : row);
            float rr = rad[row * cols + c] + offset_m;
            float *p = &out->xyz[(i * cols + c) * 3];
            p[0] = f.axis[0] + rr * cosf(th);
            p[1] = y;
            p[2] = f.axis[1] - rr * sinf(th);
        }
    }
    sim_garment_tube_triangles(out->triangles, cols, rows);
    snprintf(out->id, sizeof out->id, "shirt-%dx%d", cols, rows);
    r = attach_top_row(out, cols, &f, body_xyz, body_tris, nt, torso, why);
    r = r < 0 ? r : 0;
    free(rad);
    free(torso);
    if (r < 0)
        sim_garment_free(out);
    return r;
}
