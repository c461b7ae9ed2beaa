#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "sim_test_util.h"

/* Probed once per test executable: opening an OpenCL device builds its program. */
int simt_backends(sim_backend out[2])
{
    static int probed = 0, n = 0;
    static sim_backend found[2];
    if (!probed) {
        probed = 1;
        sim_backend all[2] = {SIM_BACKEND_C, SIM_BACKEND_OPENCL};
        /* TRYON_SIM_TEST_BACKENDS=c limits the run to the C reference */
        const char *only = getenv("TRYON_SIM_TEST_BACKENDS");
        int count = only && strcmp(only, "c") == 0 ? 1 : 2;
        for (int k = 0; k < count; k++) {
            sim_garment g = {0};
            sim_garment_drape(16, 0.1f, 0.0f, &g);
            sim_desc d = sim_default_desc();
            d.backend = all[k];
            sim *s = sim_create(&d, &g, NULL);
            sim_garment_free(&g);
            if (s)
                found[n++] = all[k];
            else if (all[k] == SIM_BACKEND_OPENCL)
                printf("# opencl backend unavailable here: C only\n");
            sim_destroy(s);
        }
    }
    for (int k = 0; k < n; k++)
        out[k] = found[k];
    return n;
}

const char *simt_backend_name(sim_backend b)
{
    return b == SIM_BACKEND_C ? "c" : "opencl";
}

sim *simt_drape(sim_backend b, sim_solver solver, int n, const sim_desc *over)
{
    sim_garment g = {0};
    if (sim_garment_drape(n * n, 0.6f, 0.35f, &g) < 0)
        return NULL;
    sim_desc d = over ? *over : sim_default_desc();
    d.backend = b;
    d.solver = solver;
    sim_reject why = {0};
    sim *s = sim_create(&d, &g, &why);
    if (!s)
        printf("# sim_create: %s: %s\n", sim_error_name(why.code), why.detail);
    sim_garment_free(&g);
    return s;
}

sim_scene *simt_sphere(void)
{
    float c[3] = {0, 0, 0};
    return sim_scene_sphere(0.2f, c, 256);
}

int simt_run(sim *s, sim_scene *sc, int frames, sim_frame_stats *last)
{
    int worst = 0;
    for (int f = 0; f < frames; f++) {
        const float *xyz, *joints;
        const int32_t *tris;
        int nv, nt;
        sim_scene_eval(sc, f / 30.0, &xyz, &nv, &tris, &nt, &joints);
        sim_frame_stats st;
        sim_reject why = {0};
        int r = sim_step(s, xyz, nv, tris, nt, &st, &why);
        if (r < 0 && r != -SIM_ERR_DIVERGED) {
            printf("# frame %d: %s: %s\n", f, sim_error_name(r), why.detail);
            return -1;
        }
        worst = st.penetrating > worst ? st.penetrating : worst;
        if (last)
            *last = st;
    }
    return worst;
}

int simt_all_finite(const sim *s)
{
    const float *x = sim_positions(s);
    for (int i = 0; i < sim_vertex_count(s) * 4; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

float simt_max_speed(const sim *s, float frame_dt)
{
    float mx = 0.0f;
    int iters = s->desc.iterations;
    for (int i = 0; i < s->cloth.nv; i++) {
        float v2 = 0.0f;
        for (int d = 0; d < 3; d++) {
            float dv = s->cloth.x[i][d] - s->cloth.x_prev[i][d];
            v2 += dv * dv;
        }
        mx = fmaxf(mx, sqrtf(v2) * (float)iters / frame_dt);
    }
    return mx;
}

int simt_scene_shirt(const char *motion, int body_verts, int shirt_verts, float hem_m,
                     sim_scene **sc, sim_garment *g, int *nv, int *nt)
{
    char err[160] = "";
    const float *xyz, *joints;
    const int32_t *tris;
    sim_reject why = {0};
    *sc = sim_scene_body(motion, body_verts, err, sizeof err);
    if (!*sc || sim_scene_eval(*sc, 0.0, &xyz, nv, &tris, nt, &joints) < 0)
        return -SIM_ERR_PARAM;
    return sim_garment_shirt(xyz, *nv, tris, *nt, joints, shirt_verts, 0.0f, hem_m, g, &why);
}

float simt_attachment_off_m(const sim *s, const sim_attachment *a, const float *xyz,
                            const int32_t *tris)
{
    const int32_t *t = &tris[a->body_triangle * 3];
    const float *v0 = &xyz[t[0] * 3], *v1 = &xyz[t[1] * 3], *v2 = &xyz[t[2] * 3];
    float e1[3] = {v1[0] - v0[0], v1[1] - v0[1], v1[2] - v0[2]};
    float e2[3] = {v2[0] - v0[0], v2[1] - v0[1], v2[2] - v0[2]};
    float nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0]};
    float len = sqrtf(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    const float *x = &sim_positions(s)[a->vertex * 4];
    float d2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        float e = x[k] - (a->bary[0] * v0[k] + a->bary[1] * v1[k] + a->bary[2] * v2[k] +
                          a->offset_m * nrm[k] / len);
        d2 += e * e;
    }
    return sqrtf(d2);
}
