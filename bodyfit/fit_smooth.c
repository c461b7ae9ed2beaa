/* One Euro filter on the pose: per joint (the root translation and each joint's rotation, each
 * a 3-vector), x' = x' + a (x - x'), a = 1 / (1 + 1 / (2 pi fc dt)), fc = min_cutoff + beta |v|,
 * v the joint's speed low-passed at FIT_SMOOTH_SPEED_CUTOFF_HZ; a joint's fc also rises with the
 * root's (beta_root times the root's speed). The speed is the vector's norm,
 * so the filter does not depend on the axes. */
#include "fit_smooth.h"

#include <math.h>
#include <string.h>

#define SMOOTH_TWO_PI 6.28318530717958647692f

static float smooth_alpha(float cutoff_hz, float dt_s)
{
    float tau = 1.0f / (SMOOTH_TWO_PI * cutoff_hz);
    return 1.0f / (1.0f + tau / dt_s);
}

void fit_smoother_init(fit_smoother *s, const fit_smooth_desc *d)
{
    memset(s, 0, sizeof *s);
    s->d = d ? *d : (fit_smooth_desc){0};
    fit_smooth_desc *x = &s->d;
    x->min_cutoff_hz = x->min_cutoff_hz > 0.0f ? x->min_cutoff_hz : FIT_SMOOTH_MIN_CUTOFF_HZ;
    x->beta_root = x->beta_root > 0.0f ? x->beta_root : FIT_SMOOTH_BETA_ROOT;
    x->beta_rot = x->beta_rot > 0.0f ? x->beta_rot : FIT_SMOOTH_BETA_ROT;
    x->frame_s = x->frame_s > 0.0f ? x->frame_s : 1.0f / 30.0f;
    x->speed_cutoff_hz =
        x->speed_cutoff_hz > 0.0f ? x->speed_cutoff_hz : FIT_SMOOTH_SPEED_CUTOFF_HZ;
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        s->lever_m[j] = 1.0f;
}

void fit_smoother_set_levers(fit_smoother *s, const float lever_m[FIT_JOINT_COUNT])
{
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        s->lever_m[j] = lever_m[j] > 0.0f ? lever_m[j] : 1.0f;
}

void fit_smoother_reset(fit_smoother *s)
{
    s->primed = 0;
}

/* One 3-vector: x filtered toward in, v its filtered speed. */
static void smooth_vec3(const fit_smooth_desc *d, float beta, float extra_hz, const float in[3],
                        float x[3], float v[3])
{
    float dt = d->frame_s, ad = smooth_alpha(d->speed_cutoff_hz, dt), speed2 = 0.0f;
    for (int k = 0; k < 3; ++k) {
        v[k] += ad * ((in[k] - x[k]) / dt - v[k]);
        speed2 += v[k] * v[k];
    }
    float a = smooth_alpha(d->min_cutoff_hz + extra_hz + beta * sqrtf(speed2), dt);
    for (int k = 0; k < 3; ++k)
        x[k] += a * (in[k] - x[k]);
}

void fit_smoother_hold(fit_smoother *s, const fit_pose *published)
{
    if (s->primed)
        s->x = *published;
}

void fit_smoother_step(fit_smoother *s, const fit_pose *in, fit_pose *out)
{
    if (!s->primed) {
        s->x = *in;
        memset(&s->dx, 0, sizeof s->dx);
        s->primed = 1;
    } else {
        smooth_vec3(&s->d, s->d.beta_root, 0.0f, in->root, s->x.root, s->dx.root);
        /* A body moving as a whole opens every joint's filter with the root's: otherwise the
         * limbs trail a walking body by centimetres (docs/bodyfit.md, "distance"). */
        const float *v = s->dx.root;
        float body_hz = s->d.beta_root * sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int j = 0; j < FIT_JOINT_COUNT; ++j)
            smooth_vec3(&s->d, s->d.beta_rot * s->lever_m[j], body_hz, in->rot[j], s->x.rot[j],
                        s->dx.rot[j]);
        fit_pose_clamp(&s->x);
    }
    *out = s->x;
}
