#include "fit_scene.h"

#include <math.h>
#include <string.h>

void fit_scene_render(fit_scene_frame *f, int with_box, const fit_model *m,
                      const float *const *vertices, int n)
{
    float c2w[16];
    rec_camera_to_world(c2w);
    rec_scene sc = rec_scene_default(with_box);
    rec_render_background(&sc, c2w, f->depth_m);
    for (int i = 0; i < n; ++i)
        rec_render_triangles(c2w, vertices[i], fit_model_triangles(m), fit_model_triangle_count(m),
                             f->depth_m);
    for (int i = 0; i < REC_WIDTH * REC_HEIGHT; ++i) {
        float z = f->depth_m[i];
        f->depth[i] = (isfinite(z) && z > 0.0f && z < 10.0f) ? (uint16_t)lrintf(z * 1000.0f) : 0;
    }
    f->view = (fit_depth_view){.width = REC_WIDTH,
                               .height = REC_HEIGHT,
                               .fx = (float)REC_FX,
                               .fy = (float)REC_FY,
                               .cx = (float)REC_CX,
                               .cy = (float)REC_CY,
                               .metres_per_unit = 0.001f,
                               .depth = f->depth};
    memcpy(f->view.camera_to_world, c2w, sizeof c2w);
}

void fit_scene_pose(const fit_model *m, const fit_pose *pose, float *vertices_out)
{
    fit_model_pose(m, pose, vertices_out, NULL);
}
