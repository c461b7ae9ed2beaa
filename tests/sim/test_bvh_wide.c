/* The 4-wide leaf tests of the nearest search against the scalar code they replace, bit for bit:
 * sim_closest_on_triangle4 lane by lane against sim_closest_on_triangle (random, degenerate and
 * tiny triangles, points on vertices, edges and faces), and sim_bvh_nearest_from against the
 * search with scalar leaves and against brute force (ties on a closed mesh, duplicated
 * triangles, hints, radii). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "collide.h"
#include "collide_bvh.h"
#include "collide_geometry.h"
#include "test_collide_util.h"

#define CLOSEST_CASES 20000
/* The nearest search's stack: the depth bound of sim/bvh.c, three more a level when 4-wide. */
#define REF_STACK (3 * 96)

/* Same bits, or both NaN (a degenerate triangle divides 0 by 0 in the face region). */
static int same_float(float a, float b)
{
    if (a != a && b != b)
        return 1;
    return memcmp(&a, &b, sizeof a) == 0;
}

/* A point for triangle (a, b, c) that lands on the features where the regions meet. */
static void pick_point(uint32_t *s, const float tri[3][3], float p[3])
{
    int kind = (int)(tc_rand(s) * 7.0f);
    float u = tc_rand(s), v = tc_rand(s) * (1.0f - u), off = tc_range(s, -0.02f, 0.02f);
    float dir[3];
    tc_direction(s, dir);
    for (int k = 0; k < 3; k++) {
        const float *a = tri[0], *b = tri[1], *c = tri[2];
        switch (kind) {
        case 0: /* a vertex exactly */
            p[k] = tri[(int)(tc_rand(s) * 2.99f)][k];
            break;
        case 1: /* an edge's midpoint */
            p[k] = 0.5f * (a[k] + b[k]);
            break;
        case 2: /* in the plane, inside */
            p[k] = a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]);
            break;
        case 3: /* off a vertex */
            p[k] = c[k] + off * dir[k];
            break;
        case 4: /* off an edge */
            p[k] = 0.5f * (b[k] + c[k]) + off * dir[k];
            break;
        default: /* anywhere near */
            p[k] = a[k] + tc_range(s, -0.1f, 0.1f);
            break;
        }
    }
}

static void random_triangle(uint32_t *s, int kind, float tri[3][3])
{
    float scale = kind == 1 ? 1e-6f : (kind == 2 ? 1e-3f : 0.05f);
    for (int j = 0; j < 3; j++)
        for (int k = 0; k < 3; k++)
            tri[j][k] = 0.3f + tc_range(s, -scale, scale);
    if (kind == 3) /* collinear: c on the line through a and b */
        for (int k = 0; k < 3; k++)
            tri[2][k] = tri[0][k] + 2.0f * (tri[1][k] - tri[0][k]);
    if (kind == 4) /* two vertices the same */
        memcpy(tri[2], tri[0], sizeof tri[0]);
    if (kind == 5) /* axis-aligned: one coordinate equal on all three */
        tri[1][1] = tri[2][1] = tri[0][1];
}

static void test_bvh_closest4_equals_scalar_lane_by_lane(void **state)
{
    (void)state;
    uint32_t s = 2024u;
    for (int n = 0; n < CLOSEST_CASES; n++) {
        float tris[4][3][3], lanes[3][3][4], p[3];
        for (int l = 0; l < 4; l++)
            random_triangle(&s, (int)(tc_rand(&s) * 6.99f), tris[l]);
        /* the point picked for one lane's triangle, so that lane sits on its features */
        pick_point(&s, tris[n & 3], p);
        for (int l = 0; l < 4; l++)
            for (int j = 0; j < 3; j++)
                for (int k = 0; k < 3; k++)
                    lanes[j][k][l] = tris[l][j][k];
        float q4[3][4], b4[3][4], d4[4];
        int32_t r4[4];
        sim_closest_on_triangle4(p, (const float(*)[3][4])lanes, q4, b4, d4, r4);
        for (int l = 0; l < 4; l++) {
            float q[3], bary[3];
            int r = sim_closest_on_triangle(p, tris[l][0], tris[l][1], tris[l][2], q, bary);
            float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
            float d2 = dx * dx + dy * dy + dz * dz;
            assert_int_equal(r4[l], r);
            assert_true(same_float(d4[l], d2));
            for (int k = 0; k < 3; k++) {
                assert_true(same_float(q4[k][l], q[k]));
                assert_true(same_float(b4[k][l], bary[k]));
            }
        }
    }
}

typedef struct mesh {
    int nv, nt;
    float (*v)[4];
    int32_t (*tris)[4];
} mesh;

/* A closed sphere (ties where the closest point is a shared vertex or edge), and after it the
   first `dups` of its triangles again under higher indices (exact ties). */
static mesh sphere_mesh(int dups)
{
    float *xyz;
    int32_t *t3;
    mesh m;
    int nt;
    tc_sphere(0.2f, 24, 16, &xyz, &m.nv, &t3, &nt);
    m.nt = nt + dups;
    m.v = malloc((size_t)m.nv * sizeof *m.v);
    m.tris = malloc((size_t)m.nt * sizeof *m.tris);
    for (int i = 0; i < m.nv; i++) {
        for (int k = 0; k < 3; k++)
            m.v[i][k] = xyz[3 * i + k];
        m.v[i][3] = 0.0f;
    }
    for (int f = 0; f < m.nt; f++) {
        for (int k = 0; k < 3; k++)
            m.tris[f][k] = t3[3 * (f % nt) + k];
        m.tris[f][3] = 0;
    }
    free(xyz);
    free(t3);
    return m;
}

/* The search as it was with scalar leaves (one sim_closest_on_triangle a leaf, in slot order),
   the reference the 4-wide leaves must reproduce, ties and order included. */
static void ref_leaf(const sim_bvh *b, const mesh *m, const float p[3], int i, int *best,
                     float *best_d2, float q[3], float bary[3])
{
    int t = b->order[i];
    float cq[3], cb[3];
    sim_closest_on_triangle(p, m->v[m->tris[t][0]], m->v[m->tris[t][1]], m->v[m->tris[t][2]], cq,
                            cb);
    float dx = p[0] - cq[0], dy = p[1] - cq[1], dz = p[2] - cq[2];
    float d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < *best_d2 || (d2 == *best_d2 && (*best < 0 || t < *best))) {
        *best = t;
        *best_d2 = d2;
        memcpy(q, cq, sizeof cq);
        memcpy(bary, cb, sizeof cb);
    }
}

static float ref_box_dist2(const float lo[4], const float hi[4], const float p[3])
{
    float d2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        float e = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0f);
        d2 += e * e;
    }
    return d2;
}

static int ref_nearest(const sim_bvh *b, const mesh *m, const float p[3], float radius, int hint,
                       float q[3], float bary[3], float *d2_out)
{
    int best = -1;
    float best_d2 = radius * radius;
    if (hint >= 0) {
        float cq[3], cb[3];
        sim_closest_on_triangle(p, m->v[m->tris[hint][0]], m->v[m->tris[hint][1]],
                                m->v[m->tris[hint][2]], cq, cb);
        float dx = p[0] - cq[0], dy = p[1] - cq[1], dz = p[2] - cq[2];
        float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 <= best_d2) {
            best = hint;
            best_d2 = d2;
            memcpy(q, cq, sizeof cq);
            memcpy(bary, cb, sizeof cb);
        }
    }
    int stack[REF_STACK], top = 0;
    float sd[REF_STACK];
    stack[top] = 0;
    sd[top++] = ref_box_dist2(b->lo[0], b->hi[0], p);
    while (top > 0) {
        top--;
        if (sd[top] > best_d2)
            continue;
        /* the shape from the 4-wide node, the boxes from its slots' binary nodes (the search
           fills the 4-wide copies when it first reaches them) */
        const sim_bvh_node4 *w = &b->wide[stack[top]];
        float d2[4];
        for (int k = 0; k < w->count; k++) {
            int bn = b->wide_node[stack[top]][k];
            d2[k] = ref_box_dist2(b->lo[bn], b->hi[bn], p);
        }
        int in[4], nin = 0;
        for (int k = 0; k < w->count; k++) {
            if (!(d2[k] <= best_d2))
                continue;
            if (w->next[k] < 0)
                ref_leaf(b, m, p, -1 - w->next[k], &best, &best_d2, q, bary);
            else
                in[nin++] = k;
        }
        assert_true(top + nin <= REF_STACK);
        for (int i = 1; i < nin; i++)
            for (int j = i; j > 0 && d2[in[j]] > d2[in[j - 1]]; j--) {
                int t = in[j];
                in[j] = in[j - 1];
                in[j - 1] = t;
            }
        for (int i = 0; i < nin; i++) {
            if (!(d2[in[i]] <= best_d2))
                continue;
            stack[top] = w->next[in[i]];
            sd[top++] = d2[in[i]];
        }
    }
    *d2_out = best_d2;
    return best;
}

/* Nearest of all within radius: the smallest distance, ties to the lower index. */
static int brute_nearest(const mesh *m, const float p[3], float radius, float *d2_out)
{
    int best = -1;
    float best_d2 = radius * radius;
    for (int f = 0; f < m->nt; f++) {
        float q[3], bary[3];
        sim_closest_on_triangle(p, m->v[m->tris[f][0]], m->v[m->tris[f][1]], m->v[m->tris[f][2]], q,
                                bary);
        float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < best_d2 || (d2 == best_d2 && best < 0)) {
            best = f;
            best_d2 = d2;
        }
    }
    *d2_out = best_d2;
    return best;
}

/* Points on the mesh's vertices, edge midpoints and face centres, pushed off along a random
   direction by up to 3 cm (or not at all), and random points around it. */
static void mesh_point(uint32_t *s, const mesh *m, float p[3])
{
    int f = (int)(tc_rand(s) * (float)(m->nt - 1));
    const float *a = m->v[m->tris[f][0]], *b = m->v[m->tris[f][1]], *c = m->v[m->tris[f][2]];
    int kind = (int)(tc_rand(s) * 4.0f);
    float off = tc_rand(s) < 0.3f ? 0.0f : tc_range(s, -0.03f, 0.03f), dir[3];
    tc_direction(s, dir);
    for (int k = 0; k < 3; k++) {
        float base = kind == 0   ? a[k]
                     : kind == 1 ? 0.5f * (a[k] + b[k])
                     : kind == 2 ? (a[k] + b[k] + c[k]) / 3.0f
                                 : tc_range(s, -0.3f, 0.3f);
        p[k] = base + off * dir[k];
    }
}

static void check_search(const mesh *m, uint32_t seed, int queries)
{
    sim_bvh b;
    assert_int_equal(sim_bvh_init(&b, m->nt), 0);
    /* built over other vertices and refitted: the 4-wide nodes must follow the refit */
    float(*v0)[4] = malloc((size_t)m->nv * sizeof *v0);
    for (int i = 0; i < m->nv; i++)
        for (int k = 0; k < 4; k++)
            v0[i][k] = 0.9f * m->v[i][k];
    sim_bvh_build(&b, (const float(*)[4])v0, (const float(*)[4])v0, (const int32_t(*)[4])m->tris,
                  m->nt, 0.004f);
    float q0[3], b0[3], d0;
    for (int n = 0; n < 200; n++) { /* fill the 4-wide nodes from the old boxes */
        float p[3];
        mesh_point(&seed, m, p);
        sim_bvh_nearest(&b, (const float(*)[4])v0, (const int32_t(*)[4])m->tris, p, INFINITY, q0,
                        b0, &d0);
    }
    sim_bvh_refit(&b, (const float(*)[4])v0, (const float(*)[4])m->v, (const int32_t(*)[4])m->tris,
                  0.004f);
    free(v0);
    const float radii[3] = {INFINITY, 0.034f, 0.002f};
    for (int n = 0; n < queries; n++) {
        float p[3];
        mesh_point(&seed, m, p);
        for (int r = 0; r < 3; r++) {
            float bd2;
            int bt = brute_nearest(m, p, radii[r], &bd2);
            int hints[3] = {-1, bt, (int)(tc_rand(&seed) * (float)(m->nt - 1))};
            for (int h = 0; h < 3; h++) {
                float q[3] = {0}, bary[3] = {0}, rq[3] = {0}, rb[3] = {0}, d = -1.0f, rd2;
                int t =
                    sim_bvh_nearest_from(&b, (const float(*)[4])m->v, (const int32_t(*)[4])m->tris,
                                         p, radii[r], hints[h], q, bary, &d);
                int rt = ref_nearest(&b, m, p, radii[r], hints[h], rq, rb, &rd2);
                assert_int_equal(t, rt);
                assert_int_equal(t, bt);
                if (t < 0)
                    continue;
                assert_true(same_float(d, sqrtf(rd2)));
                assert_true(same_float(rd2, bd2));
                for (int k = 0; k < 3; k++) {
                    assert_true(same_float(q[k], rq[k]));
                    assert_true(same_float(bary[k], rb[k]));
                }
                /* the region the search reports is the scalar closest point's of its answer */
                int region = -1;
                float q2[3], b2[3], cq[3], cb[3], d2;
                assert_int_equal(sim_bvh_nearest_region(&b, (const float(*)[4])m->v,
                                                        (const int32_t(*)[4])m->tris, p, radii[r],
                                                        hints[h], q2, b2, &d2, &region),
                                 t);
                const int32_t *f = m->tris[t];
                assert_int_equal(
                    region, sim_closest_on_triangle(p, m->v[f[0]], m->v[f[1]], m->v[f[2]], cq, cb));
            }
        }
    }
    sim_bvh_free(&b);
}

static void test_bvh_nearest_equals_scalar_leaves_bit_for_bit(void **state)
{
    (void)state;
    mesh m = sphere_mesh(0);
    check_search(&m, 99u, 3000);
    free(m.v);
    free(m.tris);
    /* every triangle twice: each query meets exact ties, the lower index wins */
    m = sphere_mesh(24 * 15 * 2);
    check_search(&m, 7u, 2000);
    free(m.v);
    free(m.tris);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bvh_closest4_equals_scalar_lane_by_lane),
        cmocka_unit_test(test_bvh_nearest_equals_scalar_leaves_bit_for_bit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
