/* Shape parameters: presets, array conversion and validation. */
#include "bodyfit.h"

#include <math.h>
#include <stdio.h>

static const char *const param_names[FIT_SHAPE_PARAMS] = {
    "height",     "shoulder_width", "chest_girth", "waist_girth", "hip_girth",
    "arm_length", "arm_girth",      "leg_length",  "leg_girth"};

/* Ranges cover adults from about the 1st to the 99th percentile (ANSUR II order of magnitude),
 * a little wider; outside them the generated body stops looking human. */
static const float param_lo[FIT_SHAPE_PARAMS] = {1.40f, 0.28f, 0.70f, 0.55f, 0.75f,
                                                 0.45f, 0.20f, 0.62f, 0.40f};
static const float param_hi[FIT_SHAPE_PARAMS] = {2.10f, 0.50f, 1.40f, 1.30f, 1.40f,
                                                 0.72f, 0.45f, 1.10f, 0.80f};

static const fit_shape presets[FIT_SHAPE_PRESETS] = {
    {1.75f, 0.38f, 1.00f, 0.85f, 1.00f, 0.56f, 0.31f, 0.86f, 0.56f},
    {1.90f, 0.40f, 0.92f, 0.74f, 0.94f, 0.62f, 0.27f, 0.97f, 0.50f},
    {1.62f, 0.42f, 1.14f, 1.02f, 1.10f, 0.50f, 0.36f, 0.74f, 0.64f},
};
static const char *const preset_names[FIT_SHAPE_PRESETS] = {"average", "slim_tall", "broad_short"};

fit_shape fit_shape_default(void)
{
    return presets[0];
}

fit_shape fit_shape_preset(int i)
{
    return (i >= 0 && i < FIT_SHAPE_PRESETS) ? presets[i] : presets[0];
}

const char *fit_shape_preset_name(int i)
{
    return (i >= 0 && i < FIT_SHAPE_PRESETS) ? preset_names[i] : "unknown";
}

void fit_shape_to_array(const fit_shape *s, float out[FIT_SHAPE_PARAMS])
{
    out[0] = s->height;
    out[1] = s->shoulder_width;
    out[2] = s->chest_girth;
    out[3] = s->waist_girth;
    out[4] = s->hip_girth;
    out[5] = s->arm_length;
    out[6] = s->arm_girth;
    out[7] = s->leg_length;
    out[8] = s->leg_girth;
}

fit_shape fit_shape_from_array(const float in[FIT_SHAPE_PARAMS])
{
    fit_shape s = {in[0], in[1], in[2], in[3], in[4], in[5], in[6], in[7], in[8]};
    return s;
}

void fit_shape_param_range(int i, float *lo, float *hi)
{
    int ok = i >= 0 && i < FIT_SHAPE_PARAMS;
    *lo = ok ? param_lo[i] : 0.0f;
    *hi = ok ? param_hi[i] : 0.0f;
}

const char *fit_shape_param_name(int i)
{
    return (i >= 0 && i < FIT_SHAPE_PARAMS) ? param_names[i] : "unknown";
}

int fit_shape_validate(const fit_shape *s, char *err, size_t errlen)
{
    if (!s) {
        if (err)
            snprintf(err, errlen, "fit shape: no shape given");
        return -FIT_ERR_ARG;
    }
    float a[FIT_SHAPE_PARAMS];
    fit_shape_to_array(s, a);
    for (int i = 0; i < FIT_SHAPE_PARAMS; ++i) {
        if (!isfinite(a[i])) {
            if (err)
                snprintf(err, errlen, "fit shape: %s is not a finite number", param_names[i]);
            return -FIT_ERR_NAN;
        }
        if (a[i] < param_lo[i] || a[i] > param_hi[i]) {
            if (err)
                snprintf(err, errlen, "fit shape: %s = %.3f m is outside %.2f..%.2f m",
                         param_names[i], a[i], param_lo[i], param_hi[i]);
            return -FIT_ERR_RANGE;
        }
    }
    return 0;
}
