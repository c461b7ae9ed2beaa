/* Checks of a depth view before its pixels are read: every field is untrusted. */
#include "fit_track.h"

#include <math.h>
#include <stdio.h>

static const char *const frame_error_names[] = {
#define X(id, text) #id,
    FIT_FRAME_ERROR_LIST(X)
#undef X
};
static const char *const frame_error_texts[] = {
#define X(id, text) text,
    FIT_FRAME_ERROR_LIST(X)
#undef X
};

const char *fit_frame_error_name(fit_frame_error e)
{
    return (e >= 0 && e < FIT_FRAME_ERROR_COUNT) ? frame_error_names[e] : "FIT_FRAME_UNKNOWN";
}

const char *fit_frame_error_text(fit_frame_error e)
{
    return (e >= 0 && e < FIT_FRAME_ERROR_COUNT) ? frame_error_texts[e] : "unknown error";
}

/* A rigid transform: finite, rotation rows orthonormal within this, bottom row 0 0 0 1. */
#define VIEW_RIGID_TOL 1e-3f

static int rigid(const float m[16])
{
    for (int i = 0; i < 16; ++i)
        if (!isfinite(m[i]))
            return 0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            float d =
                m[a * 4] * m[b * 4] + m[a * 4 + 1] * m[b * 4 + 1] + m[a * 4 + 2] * m[b * 4 + 2];
            if (fabsf(d - (a == b ? 1.0f : 0.0f)) > VIEW_RIGID_TOL)
                return 0;
        }
    return fabsf(m[12]) + fabsf(m[13]) + fabsf(m[14]) + fabsf(m[15] - 1.0f) < VIEW_RIGID_TOL;
}

fit_frame_error fit_depth_view_check(const fit_depth_view *v, char *why, size_t whylen)
{
    fit_frame_error e = FIT_FRAME_OK;
    if (!v || !v->depth || v->width < 16 || v->height < 16 || v->width > 4096 || v->height > 4096)
        e = FIT_FRAME_SIZE;
    else if (!isfinite(v->fx) || !isfinite(v->fy) || !isfinite(v->cx) || !isfinite(v->cy) ||
             v->fx < 50.0f || v->fx > 5000.0f || v->fy < 50.0f || v->fy > 5000.0f || v->cx < 0.0f ||
             v->cx > (float)v->width || v->cy < 0.0f || v->cy > (float)v->height)
        e = FIT_FRAME_INTRINSICS;
    else if (!(v->metres_per_unit >= 1e-5f && v->metres_per_unit <= 0.1f))
        e = FIT_FRAME_UNITS;
    else if (!rigid(v->camera_to_world))
        e = FIT_FRAME_POSE;
    if (e && why && whylen) {
        if (e == FIT_FRAME_SIZE)
            snprintf(why, whylen, "%s: %s (got %dx%d)", fit_frame_error_name(e),
                     fit_frame_error_text(e), v ? v->width : 0, v ? v->height : 0);
        else if (e == FIT_FRAME_INTRINSICS)
            snprintf(why, whylen, "%s: %s (got fx %g fy %g cx %g cy %g for %dx%d)",
                     fit_frame_error_name(e), fit_frame_error_text(e), v->fx, v->fy, v->cx, v->cy,
                     v->width, v->height);
        else if (e == FIT_FRAME_UNITS)
            snprintf(why, whylen, "%s: %s (got %g)", fit_frame_error_name(e),
                     fit_frame_error_text(e), v->metres_per_unit);
        else
            snprintf(why, whylen, "%s: %s", fit_frame_error_name(e), fit_frame_error_text(e));
    }
    return e;
}
