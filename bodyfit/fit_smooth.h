/* The published pose's smoothing: a One Euro filter (Casiez, Roussel and Vogel, CHI 2012) per
 * joint, whose cut-off rises with the joint's speed, so that a body standing still is still
 * and a moving one keeps up (docs/bodyfit.md). Only what is published is filtered; the tracker
 * goes on from its own unfiltered pose. */
#ifndef TRYON_FIT_SMOOTH_H
#define TRYON_FIT_SMOOTH_H

#include "bodyfit.h"

typedef struct fit_smooth_desc {
    float min_cutoff_hz;   /* cut-off at rest; 0 = the default (FIT_SMOOTH_MIN_CUTOFF_HZ) */
    float beta_root;       /* cut-off rise per m/s of the root, Hz s/m, for the root and every
                              joint; 0 = the default */
    float beta_rot;        /* cut-off rise per m/s of a joint (rad/s times its lever), Hz s/m */
    float frame_s;         /* time between frames, s; 0 = 1/30 */
    float speed_cutoff_hz; /* the speed estimate's own cut-off; 0 = FIT_SMOOTH_SPEED_CUTOFF_HZ */
} fit_smooth_desc;

#define FIT_SMOOTH_MIN_CUTOFF_HZ 0.5f
/* 16 Hz per m/s of the root, for the root and (added) every joint: a body walking 0.75 m/s
 * trails by 0.75 / (2 pi (0.5 + 12)) = 10 mm instead of 18 with 8 (docs/bodyfit.md). */
#define FIT_SMOOTH_BETA_ROOT 16.0f
#define FIT_SMOOTH_BETA_ROT  3.0f
/* The speed estimate's own cut-off (the paper's d_cutoff). Standing still, the fit's noise has
 * an apparent speed too, and that speed, not the resting cut-off, sets what is left of the
 * noise (beta_rot 3 -> 0.5: still jitter 2.05 -> 1.06 mm; 0.5 -> 0.25 Hz at rest: no change).
 * 0.7 Hz was chosen on the noisier fit of 400 points; on 800 the noise's apparent speed is
 * lower, and 1.5 Hz sees a motion start sooner: the published joints trailed the fit by up to
 * 8 cm on the walk and 14 cm on the fast swing, the bad frames published tracking
 * (docs/bodyfit.md, jitter; 0.7 / 1.0 / 1.5 Hz: still jitter at most 1.27 / 1.37 / 1.48 mm,
 * walk joints 12.6 / 11.6 / 10.7 mm). */
#define FIT_SMOOTH_SPEED_CUTOFF_HZ 1.5f

typedef struct fit_smoother {
    fit_smooth_desc d;
    fit_pose x, dx;                 /* filtered pose, filtered speed (per s) */
    float lever_m[FIT_JOINT_COUNT]; /* a joint's rad/s times this = the speed beta_rot sees */
    int primed;
} fit_smoother;

void fit_smoother_init(fit_smoother *s, const fit_smooth_desc *d);
/* Per joint, how far its rotation reaches (m): a joint's angular speed is weighed by it, so a
 * hip or a shoulder opens the filter sooner than a wrist for the same rad/s. Without a call,
 * 1 m for every joint. */
void fit_smoother_set_levers(fit_smoother *s, const float lever_m[FIT_JOINT_COUNT]);
/* Forget the past: the next pose is published as it is (a new person, a lost track). */
void fit_smoother_reset(fit_smoother *s);
/* Filters one frame's pose into out (in and out may be the same). */
void fit_smoother_step(fit_smoother *s, const fit_pose *in, fit_pose *out);
/* The pose published in place of the filter's last output (tracker.c bounds a doubted fit's
 * speed): the filter goes on from it. */
void fit_smoother_hold(fit_smoother *s, const fit_pose *published);

#endif
