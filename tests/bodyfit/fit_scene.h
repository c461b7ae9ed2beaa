/* Depth frames for the fitter's tests: the body model rendered through tryon-synth's camera
 * into tryon-synth's scene (floor, back wall, optional box), exact depth in millimetres. */
#ifndef TRYON_TEST_FIT_SCENE_H
#define TRYON_TEST_FIT_SCENE_H

#include "fit_track.h"
#include "recordings.h"

typedef struct fit_scene_frame {
    uint16_t depth[REC_WIDTH * REC_HEIGHT];
    float depth_m[REC_WIDTH * REC_HEIGHT];
    fit_depth_view view;
} fit_scene_frame;

/* Renders the background, then each of n posed vertex arrays of model m. */
void fit_scene_render(fit_scene_frame *f, int with_box, const fit_model *m,
                      const float *const *vertices, int n);
/* The body m posed: vertices_out (vertex count x 3). */
void fit_scene_pose(const fit_model *m, const fit_pose *pose, float *vertices_out);

#endif
