/* The Kinect v1 noise model. Sources (docs/recordings.md has the full story):
 * - Nguyen, Izadi, Lovell, "Modeling Kinect Sensor Noise for Improved 3D Reconstruction and
 *   Tracking", 3DIMPVT 2012: axial sigma_z(z) = 0.0012 + 0.0019 (z - 0.4)^2 m for surfaces facing
 *   the camera, lateral sigma about 0.8 px.
 * - Khoshelham & Elberink, "Accuracy and Resolution of Kinect Depth Data", Sensors 2012: depth
 *   comes from an 11-bit disparity, so its resolution falls with z^2; range 0.5-4.5 m (the
 *   manufacturer's) and holes where the projector's pattern is occluded (shadows) or at edges. */
#include <math.h>
#include <string.h>

#include "recordings.h"

/* Strict C11 has no M_PI. */
#define HALF_PI 1.57079632679489661923

static int valid(float z)
{
    return isfinite(z) && z > 0.0f;
}

/* Nguyen et al. 2012 measured up to about 70-80 degrees; past 85 the pattern is too stretched to
 * match and the Kinect reports nothing. */
#define MAX_ANGLE (85.0 / 90.0 * HALF_PI)

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

void rec_rng_seed(rec_rng *r, uint64_t seed, uint64_t stream)
{
    uint64_t x = seed ^ (stream * 0xd1b54a32d192ed03ull);
    r->s[0] = splitmix64(&x);
    r->s[1] = splitmix64(&x);
    if (!r->s[0] && !r->s[1])
        r->s[0] = 1;
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

/* xoroshiro128+ (Blackman & Vigna): small state, good enough for noise. */
uint64_t rec_rng_u64(rec_rng *r)
{
    uint64_t s0 = r->s[0], s1 = r->s[1];
    uint64_t out = s0 + s1;
    s1 ^= s0;
    r->s[0] = rotl(s0, 24) ^ s1 ^ (s1 << 16);
    r->s[1] = rotl(s1, 37);
    return out;
}

double rec_rng_uniform(rec_rng *r)
{
    return (double)(rec_rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

double rec_rng_normal(rec_rng *r)
{
    /* Box-Muller; 1 - u keeps the logarithm finite. */
    double u1 = 1.0 - rec_rng_uniform(r), u2 = rec_rng_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

rec_noise_desc rec_noise_default(int enabled, uint64_t seed)
{
    return (rec_noise_desc){.enabled = enabled,
                            .seed = seed,
                            .lateral_px = 0.8f,
                            .edge_drop = 0.5f,
                            .edge_jump_m = 0.05f,
                            .shadows = 1};
}

double rec_sigma_z(double z_m)
{
    return 0.0012 + 0.0019 * (z_m - 0.4) * (z_m - 0.4);
}

/* Nguyen et al. 2012 fit the extra noise of surfaces seen at angle theta (between the surface
 * normal and the camera ray) as a term growing like theta^2 / (pi/2 - theta)^2. */
double rec_sigma_z_angle(double z_m, double theta)
{
    double g = theta / (HALF_PI - theta);
    return rec_sigma_z(z_m) + 0.0001 / sqrt(z_m) * g * g;
}

double rec_sigma_lateral_px(double theta)
{
    return 0.8 + 0.035 * theta / (HALF_PI - theta);
}

/* Angle between the surface normal (from the clean depth's neighbours) and the camera ray at
 * pixel (u, v); -1 where the neighbourhood is not one continuous surface. */
static double surface_angle(const float *z, int u, int v, float jump)
{
    if (u < 1 || v < 1 || u >= REC_WIDTH - 1 || v >= REC_HEIGHT - 1)
        return -1.0;
    const float *c = z + v * REC_WIDTH + u;
    float l = c[-1], r = c[1], t = c[-REC_WIDTH], b = c[REC_WIDTH];
    if (!valid(*c) || !valid(l) || !valid(r) || !valid(t) || !valid(b) || fabsf(r - *c) > jump ||
        fabsf(*c - l) > jump || fabsf(b - *c) > jump || fabsf(*c - t) > jump)
        return -1.0;
    /* Back-projected neighbours: P = ((u - cx) z / fx, (v - cy) z / fy, z). */
    double dx[3] = {((u + 1 - REC_CX) * r - (u - 1 - REC_CX) * l) / REC_FX,
                    (v - REC_CY) * (r - l) / REC_FY, r - l};
    double dy[3] = {(u - REC_CX) * (b - t) / REC_FX,
                    ((v + 1 - REC_CY) * b - (v - 1 - REC_CY) * t) / REC_FY, b - t};
    double n[3] = {dx[1] * dy[2] - dx[2] * dy[1], dx[2] * dy[0] - dx[0] * dy[2],
                   dx[0] * dy[1] - dx[1] * dy[0]};
    double ray[3] = {(u - REC_CX) / REC_FX, (v - REC_CY) / REC_FY, 1.0};
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double rr = sqrt(ray[0] * ray[0] + ray[1] * ray[1] + ray[2] * ray[2]);
    if (nn <= 0.0)
        return -1.0;
    double cosang = fabs(n[0] * ray[0] + n[1] * ray[1] + n[2] * ray[2]) / (nn * rr);
    return acos(fmin(1.0, cosang));
}

/* Marks (in mark[], as REC_RAW_NONE) the pixels of one row that the projector cannot see. The
 * projector sits REC_BASELINE_M along camera +x, so a point at column u, depth z, lies on
 * projector column u - fx b / z; the projector lights only the nearest surface on each of its
 * columns. Continuous surfaces are splatted between neighbouring pixels so they leave no gaps. */
#define PROJ_PAD 160
static void shadow_row(const float *z, uint16_t *mark, float jump)
{
    float proj[REC_WIDTH + PROJ_PAD];
    for (int i = 0; i < REC_WIDTH + PROJ_PAD; i++)
        proj[i] = INFINITY;
    const double fb = REC_FX * REC_BASELINE_M;
    for (int u = 0; u < REC_WIDTH; u++) {
        if (!valid(z[u]))
            continue;
        double a = u - fb / z[u] + PROJ_PAD;
        double b = a;
        float zz = z[u];
        if (u + 1 < REC_WIDTH && valid(z[u + 1]) && fabsf(z[u + 1] - z[u]) < jump) {
            b = (u + 1) - fb / z[u + 1] + PROJ_PAD;
            zz = fminf(zz, z[u + 1]);
        }
        int lo = (int)floor(fmin(a, b) + 0.5), hi = (int)floor(fmax(a, b) + 0.5);
        for (int c = lo < 0 ? 0 : lo; c <= hi && c < REC_WIDTH + PROJ_PAD; c++)
            if (zz < proj[c])
                proj[c] = zz;
    }
    for (int u = 0; u < REC_WIDTH; u++) {
        if (!valid(z[u]))
            continue;
        int c = (int)floor(u - fb / z[u] + PROJ_PAD + 0.5);
        if (c < 0 || c >= REC_WIDTH + PROJ_PAD)
            continue;
        /* Tolerance: a surface is not its own shadow; 2 cm plus 1 % covers slanted floors. */
        if (z[u] > proj[c] + 0.02f + 0.01f * z[u])
            mark[u] = REC_RAW_NONE;
    }
}

static int is_edge(const float *z, int u, int v, float jump)
{
    float c = z[v * REC_WIDTH + u];
    static const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; k++) {
        int x = u + du[k], y = v + dv[k];
        if (x < 0 || y < 0 || x >= REC_WIDTH || y >= REC_HEIGHT)
            continue;
        float n = z[y * REC_WIDTH + x];
        if (!valid(n) || fabsf(n - c) > jump)
            return 1;
    }
    return 0;
}

static void noise_off(const float *depth_m, uint16_t *raw_out)
{
    for (int i = 0; i < REC_WIDTH * REC_HEIGHT; i++)
        raw_out[i] = valid(depth_m[i]) ? rec_mm_to_raw(depth_m[i]) : REC_RAW_NONE;
}

void rec_noise_apply(const rec_noise_desc *d, int frame, const float *depth_m, float *scratch,
                     uint16_t *raw_out)
{
    if (!d->enabled) {
        noise_off(depth_m, raw_out);
        return;
    }
    float jump = d->edge_jump_m > 0.0f ? d->edge_jump_m : 0.05f;
    float lateral = d->lateral_px > 0.0f ? d->lateral_px : 0.8f;
    rec_rng rng;
    rec_rng_seed(&rng, d->seed, (uint64_t)frame + 1);
    /* 1. Projector shadows, from the clean geometry. */
    memset(raw_out, 0, sizeof(uint16_t) * REC_WIDTH * REC_HEIGHT);
    if (d->shadows)
        for (int v = 0; v < REC_HEIGHT; v++)
            shadow_row(depth_m + v * REC_WIDTH, raw_out + v * REC_WIDTH, jump);
    /* 2. Lateral noise: each pixel reads the scene a little off its centre, more so on slanted
     * surfaces (sigma in px). Beyond MAX_ANGLE the surface returns no pattern at all. */
    for (int v = 0; v < REC_HEIGHT; v++)
        for (int u = 0; u < REC_WIDTH; u++) {
            double th = surface_angle(depth_m, u, v, jump);
            double sl = th < 0.0 ? lateral : lateral * rec_sigma_lateral_px(th) / 0.8;
            int x = u + (int)lround(rec_rng_normal(&rng) * sl);
            int y = v + (int)lround(rec_rng_normal(&rng) * sl);
            x = x < 0 ? 0 : x >= REC_WIDTH ? REC_WIDTH - 1 : x;
            y = y < 0 ? 0 : y >= REC_HEIGHT ? REC_HEIGHT - 1 : y;
            scratch[v * REC_WIDTH + u] = depth_m[y * REC_WIDTH + x];
        }
    /* 3. Edge dropouts, axial noise, range, quantisation through the disparity. */
    float drop = d->edge_drop > 0.0f ? d->edge_drop : 0.5f;
    for (int v = 0; v < REC_HEIGHT; v++)
        for (int u = 0; u < REC_WIDTH; u++) {
            int i = v * REC_WIDTH + u;
            float z = scratch[i];
            double n = rec_rng_normal(&rng), e = rec_rng_uniform(&rng);
            if (raw_out[i] == REC_RAW_NONE || !valid(z)) {
                raw_out[i] = REC_RAW_NONE;
                continue;
            }
            if (is_edge(scratch, u, v, jump) && e < drop) {
                raw_out[i] = REC_RAW_NONE;
                continue;
            }
            double th = surface_angle(depth_m, u, v, jump); /* clean geometry */
            if (th > MAX_ANGLE) {
                raw_out[i] = REC_RAW_NONE;
                continue;
            }
            raw_out[i] =
                rec_mm_to_raw(z + n * (th < 0.0 ? rec_sigma_z(z) : rec_sigma_z_angle(z, th)));
        }
}
