/* The C twins of kernels/springs.cl: integration and the spring passes. Same names, same order of
 * operations; each function handles a range so the caller can split it over threads. */
#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SIM_HAVE_AVX_PATH 1 /* an AVX clone of the spring loops, chosen at run time */
#endif

#include "cloth.h"

#if defined(__SSE2__)
/* Four springs of one colour at a time (they share no vertex): the ends gathered as float4, the
 * scalar code's operations lane by lane in the same order (no FMA, IEEE sqrt and division), so
 * every bit matches the scalar loop and kernels/springs.cl. */
typedef struct spring4 {
    __m128 xi[4], xj[4]; /* the ends as stored, w = inverse mass */
    __m128 dx, dy, dz;   /* x[j] - x[i] per lane */
    __m128 wi, wj;
} spring4;

static inline void spring4_load(spring4 *q, const float (*x)[4], const int32_t (*ends)[2], int s)
{
    __m128 d[4];
    for (int k = 0; k < 4; k++) {
        q->xi[k] = _mm_loadu_ps(x[ends[s + k][0]]);
        q->xj[k] = _mm_loadu_ps(x[ends[s + k][1]]);
        d[k] = _mm_sub_ps(q->xj[k], q->xi[k]);
    }
    _MM_TRANSPOSE4_PS(d[0], d[1], d[2], d[3]);
    q->dx = d[0], q->dy = d[1], q->dz = d[2];
    /* the w lanes: unpackhi gives (z0, z1, w0, w1), movehl takes the upper halves */
    q->wi = _mm_movehl_ps(_mm_unpackhi_ps(q->xi[2], q->xi[3]), _mm_unpackhi_ps(q->xi[0], q->xi[1]));
    q->wj = _mm_movehl_ps(_mm_unpackhi_ps(q->xj[2], q->xj[3]), _mm_unpackhi_ps(q->xj[0], q->xj[1]));
}

/* x[i] += d c wi, x[j] -= d c wj for the lanes in mask (bit k = spring s + k); w kept. */
static inline void spring4_move(const spring4 *q, float (*x)[4], const int32_t (*ends)[2], int s,
                                __m128 c, int mask)
{
    __m128 tx = _mm_mul_ps(q->dx, c), ty = _mm_mul_ps(q->dy, c), tz = _mm_mul_ps(q->dz, c);
    __m128 a[4] = {_mm_mul_ps(tx, q->wi), _mm_mul_ps(ty, q->wi), _mm_mul_ps(tz, q->wi),
                   _mm_setzero_ps()};
    __m128 b[4] = {_mm_mul_ps(tx, q->wj), _mm_mul_ps(ty, q->wj), _mm_mul_ps(tz, q->wj),
                   _mm_setzero_ps()};
    _MM_TRANSPOSE4_PS(a[0], a[1], a[2], a[3]);
    _MM_TRANSPOSE4_PS(b[0], b[1], b[2], b[3]);
    const __m128 xyz = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
    for (int k = 0; k < 4; k++) {
        if (!(mask >> k & 1))
            continue;
        __m128 ni = _mm_add_ps(q->xi[k], a[k]), nj = _mm_sub_ps(q->xj[k], b[k]);
        ni = _mm_or_ps(_mm_and_ps(xyz, ni), _mm_andnot_ps(xyz, q->xi[k]));
        nj = _mm_or_ps(_mm_and_ps(xyz, nj), _mm_andnot_ps(xyz, q->xj[k]));
        _mm_storeu_ps(x[ends[s + k][0]], ni);
        _mm_storeu_ps(x[ends[s + k][1]], nj);
    }
}

static inline __m128 spring4_len(const spring4 *q)
{
    return _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(q->dx, q->dx), _mm_mul_ps(q->dy, q->dy)),
                                  _mm_mul_ps(q->dz, q->dz)));
}
#endif

#ifdef SIM_HAVE_AVX_PATH
/* Eight springs at a time with AVX (the build is generic x86-64; the CPU is asked at run time):
 * springs k and k + 4 share a register, one in each 128-bit half, and every operation is the
 * scalar one lane by lane as in spring4. */
#define AVX __attribute__((target("avx")))

/* rows r0..r3 (x, y, z, w) to columns, in each 128-bit half */
#define TRANSPOSE8(r0, r1, r2, r3)                                                                 \
    do {                                                                                           \
        __m256 t0_ = _mm256_unpacklo_ps(r0, r1), t1_ = _mm256_unpacklo_ps(r2, r3);                 \
        __m256 t2_ = _mm256_unpackhi_ps(r0, r1), t3_ = _mm256_unpackhi_ps(r2, r3);                 \
        r0 = _mm256_shuffle_ps(t0_, t1_, _MM_SHUFFLE(1, 0, 1, 0));                                 \
        r1 = _mm256_shuffle_ps(t0_, t1_, _MM_SHUFFLE(3, 2, 3, 2));                                 \
        r2 = _mm256_shuffle_ps(t2_, t3_, _MM_SHUFFLE(1, 0, 1, 0));                                 \
        r3 = _mm256_shuffle_ps(t2_, t3_, _MM_SHUFFLE(3, 2, 3, 2));                                 \
    } while (0)

typedef struct spring8 {
    __m256 xi[4], xj[4]; /* the ends as stored, springs k and k + 4 in xi[k] */
    __m256 d[4];         /* x[j] - x[i] as rows, w lane wj - wi (unused) */
    __m256 dx, dy, dz;   /* the same per lane */
    __m256 w2;           /* wi + wj per lane */
} spring8;

/* The w lane of each row of d replaced by wi + wj before the transpose gives the inverse-mass sum
 * lane by lane without a transpose of its own. */
static inline AVX void spring8_load(spring8 *q, const float (*x)[4], const int32_t (*ends)[2],
                                    int s)
{
    __m256 r[4];
    for (int k = 0; k < 4; k++) {
        q->xi[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(x[ends[s + k][0]])),
                                        _mm_loadu_ps(x[ends[s + k + 4][0]]), 1);
        q->xj[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(x[ends[s + k][1]])),
                                        _mm_loadu_ps(x[ends[s + k + 4][1]]), 1);
        q->d[k] = _mm256_sub_ps(q->xj[k], q->xi[k]);
        r[k] = _mm256_blend_ps(q->d[k], _mm256_add_ps(q->xi[k], q->xj[k]), 0x88);
    }
    TRANSPOSE8(r[0], r[1], r[2], r[3]);
    q->dx = r[0], q->dy = r[1], q->dz = r[2], q->w2 = r[3];
}

static inline AVX __m256 spring8_len(const spring8 *q)
{
    return _mm256_sqrt_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(q->dx, q->dx), _mm256_mul_ps(q->dy, q->dy)),
                      _mm256_mul_ps(q->dz, q->dz)));
}

/* x[i] += d c wi, x[j] -= d c wj for the lanes in mask, row by row (c and w broadcast within
 * each half); the w lane is put back as it was. */
static inline AVX void spring8_move(const spring8 *q, float (*x)[4], const int32_t (*ends)[2],
                                    int s, __m256 c, int mask)
{
    for (int k = 0; k < 4; k++) {
        if (!(mask >> k & 0x11))
            continue;
        __m256 ck = k == 0   ? _mm256_permute_ps(c, 0x00)
                    : k == 1 ? _mm256_permute_ps(c, 0x55)
                    : k == 2 ? _mm256_permute_ps(c, 0xaa)
                             : _mm256_permute_ps(c, 0xff);
        __m256 t = _mm256_mul_ps(q->d[k], ck);
        __m256 ni = _mm256_add_ps(q->xi[k], _mm256_mul_ps(t, _mm256_permute_ps(q->xi[k], 0xff)));
        __m256 nj = _mm256_sub_ps(q->xj[k], _mm256_mul_ps(t, _mm256_permute_ps(q->xj[k], 0xff)));
        ni = _mm256_blend_ps(ni, q->xi[k], 0x88);
        nj = _mm256_blend_ps(nj, q->xj[k], 0x88);
        if (mask >> k & 1) {
            _mm_storeu_ps(x[ends[s + k][0]], _mm256_castps256_ps128(ni));
            _mm_storeu_ps(x[ends[s + k][1]], _mm256_castps256_ps128(nj));
        }
        if (mask >> (k + 4) & 1) {
            _mm_storeu_ps(x[ends[s + k + 4][0]], _mm256_extractf128_ps(ni, 1));
            _mm_storeu_ps(x[ends[s + k + 4][1]], _mm256_extractf128_ps(nj, 1));
        }
    }
}

/* sim_project_springs over [s, end) eight at a time; returns where it stopped. */
static AVX int project8(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                        const uint8_t *kind, const float alpha[SIM_SPRING_KINDS], int s, int end)
{
    /* the kinds' alphas in each half (vpermilps selects within a half) */
    const __m256 table = _mm256_setr_ps(alpha[0], alpha[1], alpha[2], alpha[2], alpha[0], alpha[1],
                                        alpha[2], alpha[2]);
    for (; s + 8 <= end; s += 8) {
        spring8 q;
        spring8_load(&q, (const float(*)[4])x, ends, s);
        /* alpha[kind] lane by lane: a select from the table in a register (built lane by lane
         * from memory it cost a store-forwarding stall per eight springs) */
        __m128i k8 = _mm_loadl_epi64((const __m128i *)(const void *)(kind + s));
        __m256i idx = _mm256_insertf128_si256(_mm256_castsi128_si256(_mm_cvtepu8_epi32(k8)),
                                              _mm_cvtepu8_epi32(_mm_srli_si128(k8, 4)), 1);
        __m256 al = _mm256_permutevar_ps(table, idx);
        __m256 w2 = q.w2;
        __m256 wsum = _mm256_add_ps(w2, al);
        __m256 len = spring8_len(&q);
        int mask = _mm256_movemask_ps(
            _mm256_and_ps(_mm256_cmp_ps(w2, _mm256_setzero_ps(), _CMP_NEQ_UQ),
                          _mm256_cmp_ps(len, _mm256_set1_ps(1e-9f), _CMP_NLT_UQ)));
        if (!mask)
            continue;
        __m256 c =
            _mm256_div_ps(_mm256_sub_ps(len, _mm256_loadu_ps(rest + s)), _mm256_mul_ps(len, wsum));
        spring8_move(&q, x, ends, s, c, mask);
    }
    return s;
}

/* sim_strain_limit over [s, end) eight at a time; returns where it stopped. */
static AVX int strain8(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                       const uint8_t *kind, int s, int end, float limit)
{
    const __m256 scale = _mm256_set1_ps(1.0f + limit);
    for (; s + 8 <= end; s += 8) {
        spring8 q;
        spring8_load(&q, (const float(*)[4])x, ends, s);
        __m256 wsum = q.w2;
        __m256 len = spring8_len(&q);
        __m256 lmax = _mm256_mul_ps(_mm256_loadu_ps(rest + s), scale);
        int mask =
            _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(wsum, _mm256_setzero_ps(), _CMP_NEQ_UQ),
                                             _mm256_cmp_ps(len, lmax, _CMP_NLE_UQ)));
        uint64_t k8; /* the stretch colours hold stretch springs only: all eight, as a rule */
        memcpy(&k8, kind + s, sizeof k8);
        for (int k = 0; k8 != SIM_SPRING_STRETCH * UINT64_C(0x0101010101010101) && k < 8; k++)
            if (kind[s + k] != SIM_SPRING_STRETCH)
                mask &= ~(1 << k);
        if (!mask)
            continue;
        __m256 c = _mm256_div_ps(_mm256_sub_ps(len, lmax), _mm256_mul_ps(len, wsum));
        spring8_move(&q, x, ends, s, c, mask);
    }
    return s;
}
#endif

static void verlet_scalar(float (*x)[4], float (*x_prev)[4], int begin, int end, float keep,
                          const float accel_dt2[3])
{
    for (int i = begin; i < end; i++) {
        if (x[i][3] == 0.0f)
            continue; /* pinned or attached: the driver places it */
        for (int d = 0; d < 3; d++) {
            float xi = x[i][d];
            float v = (xi - x_prev[i][d]) * keep;
            x_prev[i][d] = xi;
            x[i][d] = xi + v + accel_dt2[d];
        }
    }
}

#ifdef SIM_HAVE_AVX_PATH
/* sim_verlet two vertices at a time over [i, end) while neither is pinned; returns where it
 * stopped. Each lane the scalar loop's operations; the w lanes are put back as they were. */
static AVX int verlet2(float (*x)[4], float (*x_prev)[4], int i, int end, float keep,
                       const float accel_dt2[3])
{
    const __m256 k = _mm256_set1_ps(keep);
    const __m256 g = _mm256_setr_ps(accel_dt2[0], accel_dt2[1], accel_dt2[2], 0.0f, accel_dt2[0],
                                    accel_dt2[1], accel_dt2[2], 0.0f);
    for (; i + 2 <= end; i += 2) {
        __m256 xi = _mm256_loadu_ps(x[i]);
        if (_mm256_movemask_ps(_mm256_cmp_ps(xi, _mm256_setzero_ps(), _CMP_EQ_OQ)) & 0x88)
            break; /* a pinned vertex: the scalar loop takes these two */
        __m256 p = _mm256_loadu_ps(x_prev[i]);
        __m256 v = _mm256_mul_ps(_mm256_sub_ps(xi, p), k);
        __m256 n = _mm256_add_ps(_mm256_add_ps(xi, v), g);
        _mm256_storeu_ps(x_prev[i], _mm256_blend_ps(xi, p, 0x88));
        _mm256_storeu_ps(x[i], _mm256_blend_ps(n, xi, 0x88));
    }
    return i;
}
#endif

void sim_verlet(float (*x)[4], float (*x_prev)[4], int begin, int end, float keep,
                const float accel_dt2[3])
{
    int i = begin;
#ifdef SIM_HAVE_AVX_PATH
    if (__builtin_cpu_supports("avx"))
        while (i + 2 <= end) {
            i = verlet2(x, x_prev, i, end, keep, accel_dt2);
            if (i + 2 > end)
                break;
            verlet_scalar(x, x_prev, i, i + 2, keep, accel_dt2);
            i += 2;
        }
#endif
    verlet_scalar(x, x_prev, i, end, keep, accel_dt2);
}

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

/* Provot 1995: a spring longer than (1 + tau) rest is shortened back to it, each end moved in
 * proportion to its inverse mass (a pinned end stays). */
void sim_provot_correct(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                        const uint8_t *kind, int begin, int end, float tau)
{
    for (int s = begin; s < end; s++) {
        if (kind[s] == SIM_SPRING_BEND)
            continue; /* Provot corrects the structural (stretch, shear) springs only */
        int i = ends[s][0], j = ends[s][1];
        float wi = x[i][3], wj = x[j][3];
        float wsum = wi + wj;
        if (wsum == 0.0f)
            continue;
        float d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float lmax = rest[s] * (1.0f + tau);
        if (len <= lmax)
            continue;
        float c = (len - lmax) / (len * wsum);
        for (int a = 0; a < 3; a++) {
            x[i][a] += d[a] * c * wi;
            x[j][a] -= d[a] * c * wj;
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
#ifdef SIM_HAVE_AVX_PATH
    if (__builtin_cpu_supports("avx"))
        s = project8(x, ends, rest, kind, alpha, s, end);
#endif
#if defined(__SSE2__)
    for (; s + 4 <= end; s += 4) {
        spring4 q;
        spring4_load(&q, (const float(*)[4])x, ends, s);
        __m128 al =
            _mm_set_ps(alpha[kind[s + 3]], alpha[kind[s + 2]], alpha[kind[s + 1]], alpha[kind[s]]);
        __m128 w2 = _mm_add_ps(q.wi, q.wj);
        __m128 wsum = _mm_add_ps(w2, al);
        __m128 len = spring4_len(&q);
        /* the scalar loop's skips: wi + wj == 0, len < 1e-9 (a NaN goes on, as there) */
        int mask = _mm_movemask_ps(_mm_and_ps(_mm_cmpneq_ps(w2, _mm_setzero_ps()),
                                              _mm_cmpnlt_ps(len, _mm_set1_ps(1e-9f))));
        if (!mask)
            continue;
        __m128 c = _mm_div_ps(_mm_sub_ps(len, _mm_loadu_ps(rest + s)), _mm_mul_ps(len, wsum));
        spring4_move(&q, x, ends, s, c, mask);
    }
#endif
    for (; s < end; s++) {
        int i = ends[s][0], j = ends[s][1];
        float wi = x[i][3], wj = x[j][3];
        float wsum = wi + wj + alpha[kind[s]];
        if (wi + wj == 0.0f)
            continue;
        float d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (len < 1e-9f)
            continue;
        float c = (len - rest[s]) / (len * wsum);
        for (int a = 0; a < 3; a++) {
            x[i][a] += d[a] * c * wi;
            x[j][a] -= d[a] * c * wj;
        }
    }
}

/* Strain limiting (Provot's correction made a hard limit): stretch springs only. */
void sim_strain_limit(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                      const uint8_t *kind, int begin, int end, float limit)
{
    int s = begin;
#ifdef SIM_HAVE_AVX_PATH
    if (__builtin_cpu_supports("avx"))
        s = strain8(x, ends, rest, kind, s, end, limit);
#endif
#if defined(__SSE2__)
    const __m128 scale = _mm_set1_ps(1.0f + limit);
    for (; s + 4 <= end; s += 4) {
        spring4 q;
        spring4_load(&q, (const float(*)[4])x, ends, s);
        __m128 wsum = _mm_add_ps(q.wi, q.wj);
        __m128 len = spring4_len(&q);
        __m128 lmax = _mm_mul_ps(_mm_loadu_ps(rest + s), scale);
        /* the scalar loop's skips: not stretch, wsum == 0, len <= lmax (a NaN goes on) */
        int mask = _mm_movemask_ps(
            _mm_and_ps(_mm_cmpneq_ps(wsum, _mm_setzero_ps()), _mm_cmpnle_ps(len, lmax)));
        for (int k = 0; k < 4; k++)
            if (kind[s + k] != SIM_SPRING_STRETCH)
                mask &= ~(1 << k);
        if (!mask)
            continue;
        __m128 c = _mm_div_ps(_mm_sub_ps(len, lmax), _mm_mul_ps(len, wsum));
        spring4_move(&q, x, ends, s, c, mask);
    }
#endif
    for (; s < end; s++) {
        if (kind[s] != SIM_SPRING_STRETCH)
            continue;
        int i = ends[s][0], j = ends[s][1];
        float wi = x[i][3], wj = x[j][3];
        float wsum = wi + wj;
        if (wsum == 0.0f)
            continue;
        float d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float lmax = rest[s] * (1.0f + limit);
        if (len <= lmax)
            continue;
        float c = (len - lmax) / (len * wsum);
        for (int a = 0; a < 3; a++) {
            x[i][a] += d[a] * c * wi;
            x[j][a] -= d[a] * c * wj;
        }
    }
}

/* Point p moved alone (q stays) to within lmax of q, along q - p; nothing when it is within. */
static void pull_within(float *p, const float *q, float lmax)
{
    float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len <= lmax)
        return;
    float c = (len - lmax) / len;
    for (int a = 0; a < 3; a++)
        p[a] -= d[a] * c;
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
#if defined(__SSE2__)
    /* four vertices at a time, as the springs: each lane the scalar loop's operations */
    const __m128 scale = _mm_set1_ps(1.0f + limit);
    const __m128 xyz = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
    for (; i + 4 <= end; i += 4) {
        __m128 xi[4], d[4];
        int mask = 0;
        for (int k = 0; k < 4; k++) {
            int a = anchor[i + k];
            xi[k] = _mm_loadu_ps(x[i + k]);
            if (a >= 0 && x[i + k][3] != 0.0f)
                mask |= 1 << k;
            d[k] = _mm_sub_ps(xi[k], _mm_loadu_ps(x[a >= 0 ? a : i + k]));
        }
        if (!mask)
            continue;
        _MM_TRANSPOSE4_PS(d[0], d[1], d[2], d[3]);
        __m128 l = _mm_sqrt_ps(_mm_add_ps(
            _mm_add_ps(_mm_mul_ps(d[0], d[0]), _mm_mul_ps(d[1], d[1])), _mm_mul_ps(d[2], d[2])));
        __m128 lmax = _mm_mul_ps(_mm_loadu_ps(len + i), scale);
        /* l <= lmax: in reach (a NaN goes on). Mid-step which of four neighbours are out of
         * reach is a coin toss for the branch predictor: every tethered free vertex is stored,
         * one in reach as it was (the anchors, attached, are read by other ranges: not stored) */
        int move = mask & _mm_movemask_ps(_mm_cmpnle_ps(l, lmax));
        __m128 c = _mm_div_ps(_mm_sub_ps(l, lmax), l);
        __m128 t[4] = {_mm_mul_ps(d[0], c), _mm_mul_ps(d[1], c), _mm_mul_ps(d[2], c),
                       _mm_setzero_ps()};
        _MM_TRANSPOSE4_PS(t[0], t[1], t[2], t[3]);
        for (int k = 0; k < 4; k++) {
            if (!(mask >> k & 1))
                continue;
            __m128 n = _mm_sub_ps(xi[k], t[k]);
            __m128 sel = _mm_and_ps(xyz, _mm_castsi128_ps(_mm_set1_epi32(-(move >> k & 1))));
            _mm_storeu_ps(x[i + k], _mm_or_ps(_mm_and_ps(sel, n), _mm_andnot_ps(sel, xi[k])));
        }
    }
#endif
    for (; i < end; i++)
        if (anchor[i] >= 0 && x[i][3] != 0.0f)
            pull_within(x[i], x[anchor[i]], len[i] * (1.0f + limit));
}
