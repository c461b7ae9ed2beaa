/* Finding the person in a depth frame: depth to world points, flying pixels dropped, the floor
 * found by RANSAC, a background learned over time, and the person as the connected component
 * in the working volume nearest the camera's axis (docs/bodyfit.md, "Finding the person"). */
#include "body_internal.h" /* body_minf, body_maxf */
#include "cv_shim.h"
#include "fit_track.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Neighbours differing by more than this are a silhouette edge: the Kinect's flying pixels lie
 * between the two surfaces. Quantisation alone steps 46 mm at 4 m (ARCHITECTURE.md). */
#define SEG_EDGE_JUMP_M 0.08f
/* RANSAC: tries per search, inlier band, a floor tilted no more than acos(0.9) = 26 degrees
 * from the camera pose's up, searched again every this many frames. */
#define SEG_RANSAC_TRIES  80
#define SEG_RANSAC_BAND_M 0.03f
#define SEG_FLOOR_MIN_UP  0.9f
#define SEG_FLOOR_EVERY   30
#define SEG_RANSAC_SAMPLE 2000
/* A person-sized component reaches this high above the floor (a box or a chair does not). */
#define SEG_PERSON_TOP_M 0.9f
/* Nor is it wider across the floor than this (arm span is about the height, 2.1 m at most):
 * a wall or a sofa is. */
#define SEG_PERSON_SPAN_M 2.3f
/* Components whose centroids are this close on the floor are one person (an occluder splits
 * a body into pieces). */
#define SEG_MERGE_M   0.6f
#define SEG_MAX_COMPS 512

typedef struct comp_info {
    double sum[3];
    float top, lo[3], hi[3];
    int count;
} comp_info;

struct fit_segmenter {
    fit_segment_desc d;
    int iw, ih, w, h;
    float *depth, *world, *points, *bg, *col_ray;
    uint8_t *edge, *mask, *cand;
    int32_t *labels, *valid_idx;
    cvs_component comps[SEG_MAX_COMPS];
    comp_info ci[SEG_MAX_COMPS];
    float floor[4];
    int floor_found, frames;
    uint64_t rng;
};

static uint32_t seg_rand(fit_segmenter *s)
{
    s->rng = s->rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(s->rng >> 33);
}

fit_segmenter *fit_segmenter_create(const fit_segment_desc *d, char *err, size_t errlen)
{
    fit_segmenter *s = calloc(1, sizeof *s);
    if (!s) {
        if (err)
            snprintf(err, errlen, "fit_segmenter_create: out of memory");
        return NULL;
    }
    s->d = d ? *d : (fit_segment_desc){0};
    fit_segment_desc *x = &s->d;
    x->stride = x->stride > 0 ? x->stride : 2;
    x->min_depth_m = x->min_depth_m > 0 ? x->min_depth_m : 0.5f;
    x->max_depth_m = x->max_depth_m > 0 ? x->max_depth_m : 3.8f;
    x->max_height_m = x->max_height_m > 0 ? x->max_height_m : 2.4f;
    x->floor_band_m = x->floor_band_m > 0 ? x->floor_band_m : 0.04f;
    x->bg_margin_m = x->bg_margin_m > 0 ? x->bg_margin_m : 0.10f;
    x->min_pixels = x->min_pixels > 0 ? x->min_pixels : 300;
    s->rng = x->seed * 2654435761ULL + 1;
    if (x->stride > 8 || x->min_depth_m >= x->max_depth_m) {
        if (err)
            snprintf(err, errlen, "fit_segmenter_create: stride %d (1..8) or depth range %g..%g m",
                     x->stride, x->min_depth_m, x->max_depth_m);
        free(s);
        return NULL;
    }
    return s;
}

static void seg_free_images(fit_segmenter *s)
{
    free(s->depth);
    free(s->world);
    free(s->points);
    free(s->bg);
    free(s->col_ray);
    free(s->edge);
    free(s->mask);
    free(s->cand);
    free(s->labels);
    free(s->valid_idx);
}

void fit_segmenter_destroy(fit_segmenter *s)
{
    if (!s)
        return;
    seg_free_images(s);
    free(s);
}

/* Images are sized on the first frame; a later frame of another size is refused. */
static int seg_alloc(fit_segmenter *s, int iw, int ih)
{
    s->iw = iw;
    s->ih = ih;
    s->w = iw / s->d.stride;
    s->h = ih / s->d.stride;
    size_t n = (size_t)s->w * (size_t)s->h;
    s->depth = calloc(n, sizeof(float));
    s->world = calloc(n * 3, sizeof(float));
    s->points = calloc(n * 3, sizeof(float));
    s->bg = calloc(n, sizeof(float));
    s->col_ray = calloc((size_t)s->w, sizeof(float));
    s->edge = calloc(n, 1);
    s->mask = calloc(n, 1);
    s->cand = calloc(n, 1);
    s->labels = calloc(n, sizeof(int32_t));
    s->valid_idx = calloc(n, sizeof(int32_t));
    return s->depth && s->world && s->points && s->bg && s->col_ray && s->edge && s->mask &&
           s->cand && s->labels && s->valid_idx;
}

/* Pinhole back-projection, then camera to world. A column's (u - cx) / fx and a row's
 * (r - cy) / fy are the same for every frame's pixel: divided once a row or column (the same
 * numbers as dividing per pixel, at a 320th of the divisions). */
static int seg_sample(fit_segmenter *s, const fit_depth_view *v)
{
    const float *m = v->camera_to_world;
    int valid = 0, st = s->d.stride;
    for (int x = 0; x < s->w; ++x)
        s->col_ray[x] = ((float)(x * st) - v->cx) / v->fx;
    for (int y = 0; y < s->h; ++y) {
        const uint16_t *row = v->depth + (size_t)(y * st) * (size_t)v->width;
        float ry = ((float)(y * st) - v->cy) / v->fy;
        for (int x = 0; x < s->w; ++x) {
            int i = y * s->w + x;
            float z = (float)row[(size_t)(x * st)] * v->metres_per_unit;
            if (!(z > 0.0f) || !isfinite(z)) {
                s->depth[i] = 0.0f;
                continue;
            }
            s->depth[i] = z;
            float c[3] = {s->col_ray[x] * z, ry * z, z};
            float *w = s->world + (size_t)i * 3;
            for (int k = 0; k < 3; ++k)
                w[k] = m[k * 4] * c[0] + m[k * 4 + 1] * c[1] + m[k * 4 + 2] * c[2] + m[k * 4 + 3];
            ++valid;
        }
    }
    return valid;
}

static float plane_dist(const float pl[4], const float *p)
{
    return pl[0] * p[0] + pl[1] * p[1] + pl[2] * p[2] + pl[3];
}

/* The floor's height band: the lowest 2 cm height bin (along the camera pose's up) holding at
 * least 1 % of the points, and 15 cm above it. RANSAC draws its triples there. */
#define SEG_FLOOR_BIN_M  0.02f
#define SEG_FLOOR_BINS   512
#define SEG_FLOOR_BAND_M 0.15f

static int seg_floor_candidates(fit_segmenter *s, int nv)
{
    int hist[SEG_FLOOR_BINS] = {0};
    float lo = 1e9f;
    for (int k = 0; k < nv; ++k)
        lo = fminf(lo, s->world[(size_t)s->valid_idx[k] * 3 + 1]);
    for (int k = 0; k < nv; ++k) {
        int b = (int)((s->world[(size_t)s->valid_idx[k] * 3 + 1] - lo) / SEG_FLOOR_BIN_M);
        hist[b < SEG_FLOOR_BINS ? b : SEG_FLOOR_BINS - 1]++;
    }
    int floor_bin = -1;
    for (int b = 0; b < SEG_FLOOR_BINS && floor_bin < 0; ++b)
        if (hist[b] * 100 >= nv)
            floor_bin = b;
    if (floor_bin < 0)
        return 0;
    float y0 = lo + (float)floor_bin * SEG_FLOOR_BIN_M - SEG_FLOOR_BAND_M;
    float y1 = lo + (float)(floor_bin + 1) * SEG_FLOOR_BIN_M + SEG_FLOOR_BAND_M;
    int n = 0;
    for (int k = 0; k < nv; ++k) {
        float y = s->world[(size_t)s->valid_idx[k] * 3 + 1];
        if (y >= y0 && y <= y1)
            s->valid_idx[n++] = s->valid_idx[k];
    }
    return n;
}

/* RANSAC over the points of the floor's height band: the plane with the most inliers whose
 * normal is near the camera pose's up. Without one, the world's y = 0 (the camera pose's
 * floor). */
static void seg_floor(fit_segmenter *s)
{
    int nv = 0;
    for (int i = 0, n = s->w * s->h; i < n; ++i)
        if (s->depth[i] > 0.0f && !s->edge[i])
            s->valid_idx[nv++] = i;
    int all = nv;
    nv = nv ? seg_floor_candidates(s, nv) : 0;
    int best = 0, sample = nv < SEG_RANSAC_SAMPLE ? nv : SEG_RANSAC_SAMPLE;
    float best_pl[4] = {0.0f, 1.0f, 0.0f, 0.0f};
    for (int t = 0; t < SEG_RANSAC_TRIES && nv >= 3; ++t) {
        const float *a = s->world + (size_t)s->valid_idx[seg_rand(s) % (uint32_t)nv] * 3;
        const float *b = s->world + (size_t)s->valid_idx[seg_rand(s) % (uint32_t)nv] * 3;
        const float *c = s->world + (size_t)s->valid_idx[seg_rand(s) % (uint32_t)nv] * 3;
        float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                      u[0] * w[1] - u[1] * w[0]};
        float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(l > 1e-6f))
            continue;
        float sg = n[1] < 0.0f ? -1.0f : 1.0f;
        float pl[4] = {sg * n[0] / l, sg * n[1] / l, sg * n[2] / l, 0.0f};
        if (pl[1] < SEG_FLOOR_MIN_UP)
            continue;
        pl[3] = -(pl[0] * a[0] + pl[1] * a[1] + pl[2] * a[2]);
        int in = 0;
        for (int k = 0; k < sample; ++k) {
            int i = s->valid_idx[(size_t)k * (size_t)nv / (size_t)sample];
            in += fabsf(plane_dist(pl, s->world + (size_t)i * 3)) < SEG_RANSAC_BAND_M;
        }
        if (in > best) {
            best = in;
            memcpy(best_pl, pl, sizeof pl);
        }
    }
    /* Inliers worth at least 1 % of the image's points: a floor seen over a strip. */
    s->floor_found = sample > 0 && (double)best * nv / sample * 100.0 >= all;
    if (s->floor_found)
        memcpy(s->floor, best_pl, sizeof best_pl);
    else if (!s->frames)
        memcpy(s->floor, (float[4]){0.0f, 1.0f, 0.0f, 0.0f}, sizeof s->floor);
}

/* Candidate person pixels: in the working volume, above the floor, nearer than the background. */
static void seg_candidates(fit_segmenter *s)
{
    const fit_segment_desc *d = &s->d;
    for (int i = 0, n = s->w * s->h; i < n; ++i) {
        float z = s->depth[i];
        int ok = z >= d->min_depth_m && z <= d->max_depth_m && !s->edge[i];
        if (ok) {
            float hgt = plane_dist(s->floor, s->world + (size_t)i * 3);
            ok = hgt > d->floor_band_m && hgt < d->max_height_m;
        }
        s->cand[i] = ok && (s->bg[i] <= 0.0f || z < s->bg[i] - d->bg_margin_m);
    }
}

/* Picks the person-sized component nearest the optical axis and merges the pieces beside it. */
static int seg_pick(fit_segmenter *s, int ncomp, comp_info *ci, const float cam[3],
                    const float axis[3], int *persons)
{
    for (int c = 0; c < ncomp; ++c)
        ci[c] = (comp_info){{0, 0, 0}, -1e9f, {1e9f, 1e9f, 1e9f}, {-1e9f, -1e9f, -1e9f}, 0};
    for (int i = 0, n = s->w * s->h; i < n; ++i) {
        int l = s->labels[i] - 1;
        if (l < 0 || l >= ncomp)
            continue;
        const float *p = s->world + (size_t)i * 3;
        for (int k = 0; k < 3; ++k) {
            ci[l].sum[k] += p[k];
            ci[l].lo[k] = body_minf(ci[l].lo[k], p[k]);
            ci[l].hi[k] = body_maxf(ci[l].hi[k], p[k]);
        }
        ci[l].top = body_maxf(ci[l].top, plane_dist(s->floor, p));
        ci[l].count++;
    }
    int best = -1;
    float best_cos = -2.0f;
    *persons = 0;
    for (int c = 0; c < ncomp; ++c) {
        float wx = ci[c].hi[0] - ci[c].lo[0], wz = ci[c].hi[2] - ci[c].lo[2];
        if (ci[c].count < s->d.min_pixels || ci[c].top < SEG_PERSON_TOP_M ||
            wx * wx + wz * wz > SEG_PERSON_SPAN_M * SEG_PERSON_SPAN_M)
            continue;
        ++*persons;
        float r[3], l = 0.0f;
        for (int k = 0; k < 3; ++k) {
            r[k] = (float)(ci[c].sum[k] / ci[c].count) - cam[k];
            l += r[k] * r[k];
        }
        float cs = (r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2]) / sqrtf(l);
        if (cs > best_cos) {
            best_cos = cs;
            best = c;
        }
    }
    return best;
}

static void seg_person(fit_segmenter *s, int best, int ncomp, const comp_info *ci, fit_segment *out)
{
    float bc[3];
    for (int k = 0; k < 3; ++k)
        bc[k] = (float)(ci[best].sum[k] / ci[best].count);
    uint8_t keep[SEG_MAX_COMPS + 1] = {0};
    for (int c = 0; c < ncomp; ++c) {
        float dx = (float)(ci[c].sum[0] / (ci[c].count ? ci[c].count : 1)) - bc[0];
        float dz = (float)(ci[c].sum[2] / (ci[c].count ? ci[c].count : 1)) - bc[2];
        keep[c + 1] =
            c == best || (ci[c].count > 0 && dx * dx + dz * dz < SEG_MERGE_M * SEG_MERGE_M);
    }
    double sum[3] = {0, 0, 0};
    out->count = 0;
    out->top_y = 0.0f;
    out->touches_border = 0;
    out->touches_top = 0;
    out->touches_side = 0;
    for (int i = 0, n = s->w * s->h; i < n; ++i) {
        int l = s->labels[i];
        s->mask[i] = l > 0 && l <= ncomp && keep[l];
        if (!s->mask[i])
            continue;
        const float *p = s->world + (size_t)i * 3;
        memcpy(s->points + (size_t)out->count * 3, p, 3 * sizeof(float));
        for (int k = 0; k < 3; ++k)
            sum[k] += p[k];
        out->top_y = body_maxf(out->top_y, plane_dist(s->floor, p));
        int x = i % s->w, y = i / s->w;
        out->touches_border |= x <= 1 || y <= 1 || x >= s->w - 2 || y >= s->h - 2;
        out->touches_top |= y <= 1;
        out->touches_side |= x <= 1 || x >= s->w - 2;
        out->count++;
    }
    for (int k = 0; k < 3; ++k)
        out->centroid[k] = (float)(sum[k] / out->count);
}

/* The background keeps the farthest depth seen wherever the person is not (nor next to it:
 * the cand buffer is free by now and holds the dilated person). */
#define SEG_LEARN_GAP_PX 2

static int seg_learn(fit_segmenter *s, char *err, size_t errlen)
{
    if (cvs_dilate(s->mask, s->w, s->h, SEG_LEARN_GAP_PX, s->cand, err, errlen))
        return -1;
    for (int i = 0, n = s->w * s->h; i < n; ++i) {
        float z = s->depth[i];
        if (z > s->bg[i] && !s->cand[i])
            s->bg[i] = z;
    }
    return 0;
}

static fit_frame_error seg_fail(fit_frame_error e, const char *detail, char *why, size_t whylen)
{
    if (why && whylen)
        snprintf(why, whylen, "%s: %s%s", fit_frame_error_name(e), fit_frame_error_text(e),
                 detail ? detail : "");
    return e;
}

fit_frame_error fit_segmenter_frame(fit_segmenter *s, const fit_depth_view *v, fit_segment *out,
                                    char *why, size_t whylen)
{
    memset(out, 0, sizeof *out);
    fit_frame_error e = fit_depth_view_check(v, why, whylen);
    if (e)
        return e;
    if (!s->depth && !seg_alloc(s, v->width, v->height))
        return seg_fail(FIT_FRAME_INTERNAL, " (out of memory)", why, whylen);
    if (v->width != s->iw || v->height != s->ih) {
        char d[96];
        snprintf(d, sizeof d, " (got %dx%d, first frame %dx%d)", v->width, v->height, s->iw, s->ih);
        return seg_fail(FIT_FRAME_SIZE, d, why, whylen);
    }
    out->width = s->w;
    out->height = s->h;
    out->stride = s->d.stride;
    out->mask = s->mask;
    out->depth_m = s->depth;
    out->points = s->points;
    memset(s->mask, 0, (size_t)s->w * (size_t)s->h);
    if (seg_sample(s, v) == 0)
        return seg_fail(FIT_FRAME_EMPTY, NULL, why, whylen);
    char err[256];
    if (cvs_depth_edges(s->depth, s->w, s->h, SEG_EDGE_JUMP_M, s->edge, err, sizeof err))
        return seg_fail(FIT_FRAME_INTERNAL, err, why, whylen);
    if (s->frames % SEG_FLOOR_EVERY == 0)
        seg_floor(s);
    memcpy(out->floor, s->floor, sizeof s->floor);
    out->floor_found = s->floor_found;
    seg_candidates(s);
    int ncomp = 0;
    if (cvs_components(s->cand, s->w, s->h, s->labels, s->comps, SEG_MAX_COMPS, &ncomp, err,
                       sizeof err))
        return seg_fail(FIT_FRAME_INTERNAL, err, why, whylen);
    const float *m = v->camera_to_world;
    float cam[3] = {m[3], m[7], m[11]}, axis[3] = {m[2], m[6], m[10]};
    int best = seg_pick(s, ncomp, s->ci, cam, axis, &out->components);
    if (best >= 0)
        seg_person(s, best, ncomp, s->ci, out);
    if (seg_learn(s, err, sizeof err))
        return seg_fail(FIT_FRAME_INTERNAL, err, why, whylen);
    s->frames++;
    return best >= 0 ? FIT_FRAME_OK : seg_fail(FIT_FRAME_NOBODY, NULL, why, whylen);
}
