/* The C twins of kernels/springs.cl: integration and the spring passes. Same names, same order of
 * operations; each function handles a range so the caller can split it over threads. The
 * vectorised passes are written once (springs_pass.h) on the wide-float layer (wide.h) and made
 * here in each width: AVX where the CPU has it, then SSE2, then one lane for what is left. */
#include <math.h>
#include <string.h>

#include "cloth.h"
#include "passes.h"
#include "wide.h"

#define WF(op)   wf1_##op
#define WF_LANES WF1_LANES
#define WF_TARGET
#include "springs_pass.h"
#undef WF
#undef WF_LANES
#undef WF_TARGET

#ifdef SIM_HAVE_WF4
#define WF(op)   wf4_##op
#define WF_LANES WF4_LANES
#define WF_TARGET
#include "springs_pass.h"
#undef WF
#undef WF_LANES
#undef WF_TARGET
#endif

#ifdef SIM_HAVE_WF8
#define WF(op)    wf8_##op
#define WF_LANES  WF8_LANES
#define WF_TARGET WF8_TARGET
#include "springs_pass.h"
#undef WF
#undef WF_LANES
#undef WF_TARGET
#define HAVE_AVX() __builtin_cpu_supports("avx")
#endif

/* A pass over [begin, end) in the widest width first: PASS(name, first, end, args...) with `first`
   the variable holding where the next width starts. */
#ifdef SIM_HAVE_WF8
#define WIDEST(name, i, end, ...)                                                                  \
    do {                                                                                           \
        if (HAVE_AVX())                                                                            \
            i = wf8_##name(__VA_ARGS__, i, end);                                                   \
    } while (0)
#else
#define WIDEST(name, i, end, ...) (void)0
#endif
#ifdef SIM_HAVE_WF4
#define SSE(name, i, end, ...) (i = wf4_##name(__VA_ARGS__, i, end))
#else
#define SSE(name, i, end, ...) (void)0
#endif
#define PASS(name, i, end, ...)                                                                    \
    do {                                                                                           \
        WIDEST(name, i, end, __VA_ARGS__);                                                         \
        SSE(name, i, end, __VA_ARGS__);                                                            \
        wf1_##name(__VA_ARGS__, i, end);                                                           \
    } while (0)

/* Seed 003 / seed 000: f_i = sum_j k_ij (|x_j - x_i| - l_ij) along the spring, plus a damper on
 * the relative velocity along the spring (c = damp_ratio * k * dt, a stiffness-proportional
 * damper). Springs of one colour share no vertex, so the accumulation does not race. */
void sim_spring_forces(const float (*x)[4], const float (*x_prev)[4], const int32_t (*ends)[2],
                       const float *rest, const uint8_t *kind, const float k[SIM_SPRING_KINDS],
                       int begin, int end, float dt, float damp_ratio, float (*acc_dt2)[4])
{
    for (int s = begin; s < end; s++) {
        int i = ends[s][0], j = ends[s][1];
        float d[3], dv[3];
        for (int a = 0; a < 3; a++) {
            d[a] = x[j][a] - x[i][a];
            dv[a] = (x[j][a] - x_prev[j][a]) - (x[i][a] - x_prev[i][a]);
        }
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (len < 1e-9f)
            continue;
        float ks = k[kind[s]];
        float vrel = (dv[0] * d[0] + dv[1] * d[1] + dv[2] * d[2]) / len / dt;
        float f = ks * (len - rest[s]) + damp_ratio * ks * dt * vrel; /* N, along d */
        float fdt2 = f * dt * dt / len;
        for (int a = 0; a < 3; a++) {
            acc_dt2[i][a] += d[a] * fdt2 * x[i][3];
            acc_dt2[j][a] -= d[a] * fdt2 * x[j][3];
        }
    }
}

void sim_verlet_forces(float (*x)[4], float (*x_prev)[4], const float (*acc_dt2)[4], int begin,
                       int end, float keep, const float g_dt2[3])
{
    for (int i = begin; i < end; i++) {
        if (x[i][3] == 0.0f)
            continue;
        for (int d = 0; d < 3; d++) {
            float xi = x[i][d];
            float v = (xi - x_prev[i][d]) * keep;
            x_prev[i][d] = xi;
            x[i][d] = xi + v + acc_dt2[i][d] + g_dt2[d];
        }
    }
}

/* XPBD (Macklin et al. 2016), one Gauss-Seidel pass in small steps (Macklin et al. 2019): with
 * one pass per substep the multiplier starts at zero, so dlambda = -C / (wi + wj + alpha) with
 * alpha = 1 / (k dt^2), the compliance of a spring of stiffness k. */
void sim_project_springs(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                         const uint8_t *kind, const float alpha[SIM_SPRING_KINDS], int begin,
                         int end)
{
    int s = begin;
    PASS(springs, s, end, x, ends, rest, kind, alpha, 0u, 0.0f);
}

/* The clamp (Provot 1995; the strain limit is the clamp on stretch springs, a hard limit). */
void sim_clamp_springs(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                       const uint8_t *kind, int begin, int end, unsigned kinds, float ratio)
{
    int s = begin;
    PASS(springs, s, end, x, ends, rest, kind, NULL, kinds, ratio);
}

void sim_verlet(float (*x)[4], float (*x_prev)[4], int begin, int end, float keep,
                const float accel_dt2[3])
{
    int i = begin;
    PASS(verlet, i, end, x, x_prev, keep, accel_dt2);
}

/* p (its x_prev in the post-stabilisation's bracket: -(x - x_prev), the step's displacement
 * negated) moved alone to within lmax of q, and where it was farther, its velocity away from q
 * removed: the velocity modification of Vassilev, Spanlang & Chrysanthou (2001), seed 003's remedy
 * for super-elasticity, one-sided as the hierarchies are (q is final, as if infinitely heavy).
 * Without it the kept velocity re-stretches what the pass took out: a drape of 14,884 vertices
 * under the support hierarchy gained speed until it slid off the sphere, and the walk's p99
 * strain was 1.33 % where it is 1.08 % (docs/sim.md, "The support hierarchy"). It can only slow p.
 */
static void pull_within_still(float *p, float *p_prev, const float *q, float lmax)
{
    float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len <= lmax)
        return;
    float away = -(p_prev[0] * d[0] + p_prev[1] * d[1] + p_prev[2] * d[2]) / len;
    float c = (len - lmax) / len;
    for (int a = 0; a < 3; a++)
        p[a] -= d[a] * c;
    if (away > 0.0f)
        for (int a = 0; a < 3; a++)
            p_prev[a] += away * (d[a] / len);
}

/* Shock propagation (Guendelman, Bridson & Fedkiw 2003) applied to strain limiting: processed
 * from the attachments outward, each vertex is corrected against its already-final parents as if
 * they were infinitely heavy, so one pass removes a stretch that Gauss-Seidel sweeps remove one
 * spring per sweep (the one-sided projection of follow-the-leader, Mueller et al. 2012, on the
 * springs of a level graph). */
void sim_strain_hierarchy(float (*x)[4], float (*x_prev)[4], const int32_t *vertex,
                          const int32_t *parent_start, const int32_t *parent, const float *rest,
                          int begin, int end, float limit)
{
    for (int e = begin; e < end; e++) {
        int i = vertex[e];
        if (x[i][3] == 0.0f)
            continue; /* pinned: the driver places it */
        for (int k = parent_start[e]; k < parent_start[e + 1]; k++)
            pull_within_still(x[i], x_prev[i], x[parent[k]], rest[k] * (1.0f + limit));
    }
}

int sim_support_levels(const sim_cloth *c, int root, int32_t *level, int32_t *queue)
{
    for (int v = 0; v < c->nv; v++)
        level[v] = -1;
    if (root < 0 || root >= c->nv)
        return 0;
    level[root] = 0;
    queue[0] = root;
    int head = 0, tail = 1;
    while (head < tail) {
        int v = queue[head++];
        for (int k = c->adj_start[v]; k < c->adj_start[v + 1]; k++) {
            const int32_t *e = c->ends[c->adj_spring[k]];
            int u = e[0] == v ? e[1] : e[0];
            if (level[u] < 0) {
                level[u] = level[v] + 1;
                queue[tail++] = u;
            }
        }
    }
    memmove(queue, queue + 1, (size_t)(tail - 1) * sizeof *queue);
    return tail - 1;
}

/* The support hierarchy's pass for one vertex: as sim_strain_hierarchy, its parents being its
 * stretch neighbours one level nearer the root. */
void sim_support_pull(float (*x)[4], float (*x_prev)[4], const sim_cloth *c, const int32_t *level,
                      int v, float limit)
{
    if (x[v][3] == 0.0f)
        return;
    for (int k = c->adj_start[v]; k < c->adj_start[v + 1]; k++) {
        int s = c->adj_spring[k];
        int u = c->ends[s][0] == v ? c->ends[s][1] : c->ends[s][0];
        if (level[u] == level[v] - 1)
            pull_within_still(x[v], x_prev[v], x[u], c->rest[s] * (1.0f + limit));
    }
}

void sim_post_begin(float (*x)[4], float (*x_prev)[4], int begin, int end)
{
    for (int i = begin; i < end; i++)
        if (x[i][3] != 0.0f)
            for (int d = 0; d < 3; d++)
                x_prev[i][d] -= x[i][d];
}

void sim_post_end(float (*x)[4], float (*x_prev)[4], int begin, int end)
{
    for (int i = begin; i < end; i++)
        if (x[i][3] != 0.0f)
            for (int d = 0; d < 3; d++)
                x_prev[i][d] += x[i][d];
}

/* Long-range attachments (Kim, Tessendorf, Thuerey 2012): a unilateral constraint from each free
 * vertex to its nearest attached vertex. Only the free end moves, so vertices are independent and
 * the pass needs no colouring. It carries the weight of a hanging garment in one step where
 * Gauss-Seidel over springs needs one sweep per row. */
void sim_tethers(float (*x)[4], const int32_t *anchor, const float *len, int begin, int end,
                 float limit)
{
    int i = begin;
    PASS(tethers, i, end, x, anchor, len, limit);
}
