/* From a CONTROL request to a garment: the names the mirror offers mapped onto what the sim can
 * make today (the generated shirt, OBJ files, sewing patterns: made by outfit_pattern.c) and the
 * fabric presets. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cloth.h"
#include "sim.h"

/* The shirt's ease (gap to the skin) per size. M is sim_garment_shirt's own default (15 mm); a
 * size step in ready-to-wear grading is about 4 cm of chest girth, about 6 mm of radius. */
static const float size_offset_m[3] = {0.009f, 0.015f, 0.021f};
/* File garments: the same 6 mm per size on a torso of about 0.15 m radius. */
static const float size_scale[3] = {0.96f, 1.0f, 1.04f};

typedef struct named_garment {
    const char *name;
    float hem_m; /* below the pelvis joint (sim_garment_shirt) */
} named_garment;
/* hems from docs/sim.md, "The hem and the error": 0.12 m at the hips, 0.25 m a tunic */
static const named_garment garments[] = {{"shirt", 0.12f}, {"tunic", 0.25f}};

/* Interim presets (areal density kg/m^2, membrane stretch / shear / bend N/m) until the fabric
 * library lands; cotton is the solver's default fabric. */
typedef struct named_fabric {
    const char *name;
    sim_fabric f;
} named_fabric;
static const named_fabric fabrics[] = {
    {"cotton", {0.20f, 1000.0f, 100.0f, 2.0f}},
    {"denim", {0.40f, 3000.0f, 300.0f, 8.0f}},
    {"jersey", {0.18f, 400.0f, 30.0f, 0.5f}},
    {"silk", {0.08f, 800.0f, 40.0f, 0.3f}},
};

#define COUNT(a) ((int)(sizeof(a) / sizeof(a)[0]))

const char *sim_size_name(sim_size s)
{
    static const char *names[3] = {"S", "M", "L"};
    return s >= SIM_SIZE_S && s <= SIM_SIZE_L ? names[s] : "?";
}

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), k = strlen(tail);
    return n > k && strcmp(s + n - k, tail) == 0;
}

int sim_outfit_resolve(const char *garment, int size, const char *fabric, sim_outfit *out,
                       sim_reject *why)
{
    memset(out, 0, sizeof *out);
    if (!garment || !*garment || strlen(garment) >= sizeof out->garment)
        return sim_reject_set(why, SIM_ERR_PARAM, "garment name empty or too long");
    if (size < SIM_SIZE_S || size > SIM_SIZE_L)
        return sim_reject_set(why, SIM_ERR_PARAM, "size %d (S, M, L = 0, 1, 2)", size);
    snprintf(out->garment, sizeof out->garment, "%s", garment);
    out->size = (sim_size)size;
    out->offset_m = size_offset_m[size];
    out->scale = size_scale[size];
    out->is_pattern = ends_with(garment, ".json");
    out->is_file = ends_with(garment, ".obj") || out->is_pattern;
    int known = out->is_file;
    for (int i = 0; i < COUNT(garments) && !known; i++)
        if (strcmp(garment, garments[i].name) == 0) {
            out->hem_m = garments[i].hem_m;
            known = 1;
        }
    if (!known)
        return sim_reject_set(why, SIM_ERR_PARAM,
                              "garment '%.60s': not shirt, tunic, a .obj or a .json", garment);
    const char *fname = fabric && *fabric ? fabric : "cotton";
    int fi = -1;
    for (int i = 0; i < COUNT(fabrics); i++)
        if (strcmp(fname, fabrics[i].name) == 0)
            fi = i;
    if (fi < 0)
        return sim_reject_set(why, SIM_ERR_PARAM,
                              "fabric '%.60s': not cotton, denim, jersey or silk", fname);
    snprintf(out->fabric_name, sizeof out->fabric_name, "%s", fabrics[fi].name);
    out->fabric = fabrics[fi].f;
    const char *base = out->is_file ? strrchr(garment, '/') : NULL;
    snprintf(out->id, sizeof out->id, "%.60s %s %s", base ? base + 1 : garment,
             sim_size_name(out->size), out->fabric_name);
    return 0;
}

int sim_outfit_same(const sim_outfit *a, const sim_outfit *b)
{
    return strcmp(a->garment, b->garment) == 0 && a->size == b->size &&
           strcmp(a->fabric_name, b->fabric_name) == 0 && a->hem_m == b->hem_m;
}

/* A file garment graded by scaling x and z about its centroid's vertical axis. */
static void scale_about_axis(sim_garment *g, float s)
{
    double cx = 0.0, cz = 0.0;
    for (int i = 0; i < g->num_vertices; i++) {
        cx += g->xyz[i * 3 + 0];
        cz += g->xyz[i * 3 + 2];
    }
    cx /= g->num_vertices;
    cz /= g->num_vertices;
    for (int i = 0; i < g->num_vertices; i++) {
        g->xyz[i * 3 + 0] = (float)cx + s * (g->xyz[i * 3 + 0] - (float)cx);
        g->xyz[i * 3 + 2] = (float)cz + s * (g->xyz[i * 3 + 2] - (float)cz);
    }
}

int sim_outfit_make(const sim_outfit *o, const float *body_xyz, int nv, const int32_t *body_tris,
                    int nt, const float *joints_xyz, int n_vertices, sim_garment *out,
                    sim_reject *why)
{
    int r;
    if (o->is_pattern) /* needs the body model and garments/: the caller's library */
        return sim_reject_set(why, SIM_ERR_ARG, "%.80s: a pattern (sim_outfit_make_pattern)",
                              o->garment);
    if (o->is_file) {
        r = sim_garment_load_obj(o->garment, out, why);
        if (r == 0 && o->scale != 1.0f)
            scale_about_axis(out, o->scale);
    } else {
        r = sim_garment_shirt(body_xyz, nv, body_tris, nt, joints_xyz, n_vertices, o->offset_m,
                              o->hem_m, out, why);
    }
    if (r == 0)
        snprintf(out->id, sizeof out->id, "%.63s", o->id);
    return r;
}
