/* Kinect v1 disparity <-> depth, exactly as libfreenect converts it, so that a dump written here
 * reads back through any libfreenect user (FREENECT_DEPTH_MM) as the depth we meant. */
#include <math.h>

#include "recordings.h"

/* libfreenect registration.c: parameter_coefficient = 4, shift_scale = 10, S2D_CONST_OFFSET =
 * 0.375, and the table stops at DEPTH_MAX_METRIC_VALUE = 10000 mm. */
#define PARAM_COEFF      4.0
#define SHIFT_SCALE      10.0
#define S2D_CONST_OFFSET 0.375
#define MAX_METRIC_MM    10000.0

static double raw_to_mm_exact(double raw)
{
    double fixed_ref_x = ((raw - PARAM_COEFF * REC_CONST_SHIFT) / PARAM_COEFF) - S2D_CONST_OFFSET;
    double metric = fixed_ref_x * REC_ZP_PIXEL_MM;
    double denom = REC_ZP_EMITTER_CM - metric;
    if (denom <= 0.0)
        return -1.0;
    return SHIFT_SCALE * ((metric * REC_ZP_REF_DIST_MM / denom) + REC_ZP_REF_DIST_MM);
}

uint16_t rec_raw_to_mm(uint16_t raw)
{
    if (raw >= REC_RAW_NONE)
        return 0;
    double mm = raw_to_mm_exact(raw);
    if (!(mm > 0.0) || mm >= MAX_METRIC_MM)
        return 0;
    return (uint16_t)mm; /* libfreenect truncates when it stores into its uint16_t table */
}

void rec_raw_to_mm_table(uint16_t table[REC_RAW_LEVELS])
{
    for (int i = 0; i < REC_RAW_LEVELS; i++)
        table[i] = rec_raw_to_mm((uint16_t)i);
}

uint16_t rec_mm_to_raw(double depth_m)
{
    if (!isfinite(depth_m) || depth_m < REC_RANGE_MIN_M || depth_m > REC_RANGE_MAX_M)
        return REC_RAW_NONE;
    /* Invert the formula: mm = 10 * R * E / (E - metric) => metric = E - 10 R E / mm. */
    double mm = depth_m * 1000.0;
    double metric = REC_ZP_EMITTER_CM - SHIFT_SCALE * REC_ZP_REF_DIST_MM * REC_ZP_EMITTER_CM / mm;
    double raw =
        (metric / REC_ZP_PIXEL_MM + S2D_CONST_OFFSET) * PARAM_COEFF + PARAM_COEFF * REC_CONST_SHIFT;
    long r0 = lround(floor(raw));
    long best = -1;
    double best_err = INFINITY;
    /* The stored table truncates, so check the neighbours rather than trust rounding. */
    for (long r = r0 - 1; r <= r0 + 2; r++) {
        if (r < 0 || r >= REC_RAW_NONE)
            continue;
        uint16_t v = rec_raw_to_mm((uint16_t)r);
        if (v == 0)
            continue;
        double err = fabs((double)v - mm);
        if (err < best_err) {
            best_err = err;
            best = r;
        }
    }
    return best < 0 ? REC_RAW_NONE : (uint16_t)best;
}
