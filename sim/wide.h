/* Private to sim/: the wide-float layer the spring passes are written on (springs_pass.h). A
 * vector of lanes of float with the few operations the passes use, in three widths: wf1 (one
 * lane, plain C), wf4 (SSE2, four lanes), wf8 (AVX, eight lanes, for a CPU that has it: the build
 * is generic x86-64, the CPU is asked at run time). Every operation is the IEEE one lane by lane
 * (no FMA, IEEE sqrt and division), so a pass gives the same bits at every width, and the same as
 * kernels/springs.cl.
 *
 * Lane k holds item k of a run of WF lanes (a spring, a vertex). rows() gathers the float4 rows
 * x[idx[k * stride]] as four vectors (x, y, z, w per lane); store() writes the rows of the lanes
 * in mask (bit k = lane k) back, their w from the fourth vector (the one rows() gave: kept; the
 * one-lane width writes x, y, z only). Comparisons return such masks; NaN compares unordered (a
 * NaN lane is "not equal", "not less", "not less or equal", as C's !(a < b) is true for NaN). */
#ifndef TRYON_SIM_WIDE_H
#define TRYON_SIM_WIDE_H

#include <math.h>
#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#define SIM_HAVE_WF4 1
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SIM_HAVE_WF8 1
#define WF8_TARGET   __attribute__((target("avx")))
#endif

/* Whether the n <= 8 bytes at p are all zero (a run of springs all of kind 0, stretch: the strain
   limit's colours as a rule, which then need no look at each lane's kind). */
static inline int wf_bytes_zero(const uint8_t *p, int n)
{
    uint64_t v = 0;
    memcpy(&v, p, (size_t)n);
    return v == 0;
}

/* ---- wf1: one lane, plain C ------------------------------------------------------------------ */
#define WF1_LANES 1
typedef float wf1_t;

static inline wf1_t wf1_set1(float a)
{
    return a;
}
static inline wf1_t wf1_load(const float *p)
{
    return p[0];
}
static inline wf1_t wf1_add(wf1_t a, wf1_t b)
{
    return a + b;
}
static inline wf1_t wf1_sub(wf1_t a, wf1_t b)
{
    return a - b;
}
static inline wf1_t wf1_mul(wf1_t a, wf1_t b)
{
    return a * b;
}
static inline wf1_t wf1_div(wf1_t a, wf1_t b)
{
    return a / b;
}
static inline wf1_t wf1_sqrt(wf1_t a)
{
    return sqrtf(a);
}
static inline int wf1_neq(wf1_t a, wf1_t b)
{
    return a != b;
}
static inline int wf1_nlt(wf1_t a, wf1_t b)
{
    return !(a < b);
}
static inline int wf1_nle(wf1_t a, wf1_t b)
{
    return !(a <= b);
}
static inline wf1_t wf1_select(int mask, wf1_t a, wf1_t b)
{
    return mask & 1 ? a : b;
}
/* table[kind[k]] per lane, kinds 0..2: wfN_table_of once before a loop (alpha may alias what the
   loop stores, so the compiler would load it again for every run), then wfN_lookup per run */
typedef struct wf1_table {
    float t[3];
} wf1_table;

static inline wf1_table wf1_table_of(const float *a)
{
    return (wf1_table){{a[0], a[1], a[2]}};
}

static inline wf1_t wf1_lookup(const wf1_table *t, const uint8_t *kind)
{
    return t->t[kind[0]];
}

static inline void wf1_rows(const float (*x)[4], const int32_t *idx, int stride, wf1_t r[4])
{
    (void)stride;
    for (int d = 0; d < 4; d++)
        r[d] = x[idx[0]][d];
}

static inline void wf1_store(float (*x)[4], const int32_t *idx, int stride, const wf1_t r[4],
                             int mask)
{
    (void)stride;
    if (mask & 1)
        for (int d = 0; d < 3; d++)
            x[idx[0]][d] = r[d];
}

/* ---- wf4: SSE2, four lanes ------------------------------------------------------------------- */
#ifdef SIM_HAVE_WF4
#define WF4_LANES 4
typedef __m128 wf4_t;

static inline wf4_t wf4_set1(float a)
{
    return _mm_set1_ps(a);
}
static inline wf4_t wf4_load(const float *p)
{
    return _mm_loadu_ps(p);
}
static inline wf4_t wf4_add(wf4_t a, wf4_t b)
{
    return _mm_add_ps(a, b);
}
static inline wf4_t wf4_sub(wf4_t a, wf4_t b)
{
    return _mm_sub_ps(a, b);
}
static inline wf4_t wf4_mul(wf4_t a, wf4_t b)
{
    return _mm_mul_ps(a, b);
}
static inline wf4_t wf4_div(wf4_t a, wf4_t b)
{
    return _mm_div_ps(a, b);
}
static inline wf4_t wf4_sqrt(wf4_t a)
{
    return _mm_sqrt_ps(a);
}
static inline int wf4_neq(wf4_t a, wf4_t b)
{
    return _mm_movemask_ps(_mm_cmpneq_ps(a, b));
}
static inline int wf4_nlt(wf4_t a, wf4_t b)
{
    return _mm_movemask_ps(_mm_cmpnlt_ps(a, b));
}
static inline int wf4_nle(wf4_t a, wf4_t b)
{
    return _mm_movemask_ps(_mm_cmpnle_ps(a, b));
}

static inline wf4_t wf4_select(int mask, wf4_t a, wf4_t b)
{
    __m128 m = _mm_castsi128_ps(
        _mm_set_epi32(-(mask >> 3 & 1), -(mask >> 2 & 1), -(mask >> 1 & 1), -(mask & 1)));
    return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b));
}

typedef wf1_table wf4_table;
static inline wf4_table wf4_table_of(const float *a)
{
    return wf1_table_of(a);
}
static inline wf4_t wf4_lookup(const wf4_table *t, const uint8_t *kind)
{
    return _mm_set_ps(t->t[kind[3]], t->t[kind[2]], t->t[kind[1]], t->t[kind[0]]);
}

static inline void wf4_rows(const float (*x)[4], const int32_t *idx, int stride, wf4_t r[4])
{
    for (int k = 0; k < 4; k++)
        r[k] = _mm_loadu_ps(x[idx[k * stride]]);
    _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
}

static inline void wf4_store(float (*x)[4], const int32_t *idx, int stride, const wf4_t r[4],
                             int mask)
{
    __m128 t[4] = {r[0], r[1], r[2], r[3]};
    _MM_TRANSPOSE4_PS(t[0], t[1], t[2], t[3]);
    for (int k = 0; k < 4; k++)
        if (mask >> k & 1)
            _mm_storeu_ps(x[idx[k * stride]], t[k]);
}
#endif

/* ---- wf8: AVX, eight lanes ------------------------------------------------------------------- */
#ifdef SIM_HAVE_WF8
#define WF8_LANES 8
typedef __m256 wf8_t;

/* rows r0..r3 to columns within each 128-bit half: with rows k and k + 4 in the halves of r[k],
   the columns come out as lanes 0..7 in order */
#define WF8_TRANSPOSE(r0, r1, r2, r3)                                                              \
    do {                                                                                           \
        __m256 t0_ = _mm256_unpacklo_ps(r0, r1), t1_ = _mm256_unpacklo_ps(r2, r3);                 \
        __m256 t2_ = _mm256_unpackhi_ps(r0, r1), t3_ = _mm256_unpackhi_ps(r2, r3);                 \
        r0 = _mm256_shuffle_ps(t0_, t1_, _MM_SHUFFLE(1, 0, 1, 0));                                 \
        r1 = _mm256_shuffle_ps(t0_, t1_, _MM_SHUFFLE(3, 2, 3, 2));                                 \
        r2 = _mm256_shuffle_ps(t2_, t3_, _MM_SHUFFLE(1, 0, 1, 0));                                 \
        r3 = _mm256_shuffle_ps(t2_, t3_, _MM_SHUFFLE(3, 2, 3, 2));                                 \
    } while (0)

static inline WF8_TARGET wf8_t wf8_set1(float a)
{
    return _mm256_set1_ps(a);
}
static inline WF8_TARGET wf8_t wf8_load(const float *p)
{
    return _mm256_loadu_ps(p);
}
static inline WF8_TARGET wf8_t wf8_add(wf8_t a, wf8_t b)
{
    return _mm256_add_ps(a, b);
}
static inline WF8_TARGET wf8_t wf8_sub(wf8_t a, wf8_t b)
{
    return _mm256_sub_ps(a, b);
}
static inline WF8_TARGET wf8_t wf8_mul(wf8_t a, wf8_t b)
{
    return _mm256_mul_ps(a, b);
}
static inline WF8_TARGET wf8_t wf8_div(wf8_t a, wf8_t b)
{
    return _mm256_div_ps(a, b);
}
static inline WF8_TARGET wf8_t wf8_sqrt(wf8_t a)
{
    return _mm256_sqrt_ps(a);
}

static inline WF8_TARGET int wf8_neq(wf8_t a, wf8_t b)
{
    return _mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_NEQ_UQ));
}

static inline WF8_TARGET int wf8_nlt(wf8_t a, wf8_t b)
{
    return _mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_NLT_UQ));
}

static inline WF8_TARGET int wf8_nle(wf8_t a, wf8_t b)
{
    return _mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_NLE_UQ));
}

static inline WF8_TARGET wf8_t wf8_select(int mask, wf8_t a, wf8_t b)
{
    __m256 m = _mm256_castsi256_ps(
        _mm256_setr_epi32(-(mask & 1), -(mask >> 1 & 1), -(mask >> 2 & 1), -(mask >> 3 & 1),
                          -(mask >> 4 & 1), -(mask >> 5 & 1), -(mask >> 6 & 1), -(mask >> 7 & 1)));
    return _mm256_blendv_ps(b, a, m);
}

/* a select from the table in a register (built lane by lane from memory it cost a
   store-forwarding stall per eight springs) */
typedef struct wf8_table {
    __m256 t;
} wf8_table;

static inline WF8_TARGET wf8_table wf8_table_of(const float *a)
{
    return (wf8_table){_mm256_setr_ps(a[0], a[1], a[2], a[2], a[0], a[1], a[2], a[2])};
}

static inline WF8_TARGET wf8_t wf8_lookup(const wf8_table *t, const uint8_t *kind)
{
    __m128i k8 = _mm_loadl_epi64((const __m128i *)(const void *)kind);
    __m256i idx = _mm256_insertf128_si256(_mm256_castsi128_si256(_mm_cvtepu8_epi32(k8)),
                                          _mm_cvtepu8_epi32(_mm_srli_si128(k8, 4)), 1);
    return _mm256_permutevar_ps(t->t, idx);
}

static inline WF8_TARGET void wf8_rows(const float (*x)[4], const int32_t *idx, int stride,
                                       wf8_t r[4])
{
    for (int k = 0; k < 4; k++)
        r[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(x[idx[k * stride]])),
                                    _mm_loadu_ps(x[idx[(k + 4) * stride]]), 1);
    WF8_TRANSPOSE(r[0], r[1], r[2], r[3]);
}

static inline WF8_TARGET void wf8_store(float (*x)[4], const int32_t *idx, int stride,
                                        const wf8_t r[4], int mask)
{
    __m256 t[4] = {r[0], r[1], r[2], r[3]};
    WF8_TRANSPOSE(t[0], t[1], t[2], t[3]); /* t[k]: rows k and k + 4 */
    for (int k = 0; k < 4; k++) {
        if (mask >> k & 1)
            _mm_storeu_ps(x[idx[k * stride]], _mm256_castps256_ps128(t[k]));
        if (mask >> (k + 4) & 1)
            _mm_storeu_ps(x[idx[(k + 4) * stride]], _mm256_extractf128_ps(t[k], 1));
    }
}
#endif

#endif
