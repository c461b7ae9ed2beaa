/* Private to garments/: the seed's dressing pieces. */
#ifndef TRYON_GARMENTS_DRESS_INTERNAL_H
#define TRYON_GARMENTS_DRESS_INTERNAL_H

#include "pattern_internal.h"

/* Front (largest depth) and back (smallest) depth of the body per pixel seen along one axis
 * (0 = x, 1 = y, 2 = z: the seed's front/back pair), and the outward face normal there;
 * empty pixels hold -inf / +inf. Rendered for the three axes. */
typedef struct gar_body_maps {
    int axis, w, h;
    float x0, y0, pixel_m;
    float *front_z, *back_z;
    float *front_n, *back_n; /* [pixel][3] */
} gar_body_maps;
int gar_body_maps_render(const float *xyz, int nv, const int32_t *tris, int nt, float pixel_m,
                         gar_body_maps bm[3]);
void gar_body_maps_free(gar_body_maps *bm);
/* 1 if p is inside all three slabs (or within margin_m): push is the move out to margin_m
 * along the normal n of the view that finds it shallowest. */
int gar_body_maps_collide(const gar_body_maps bm[3], const float p[3], float margin_m,
                          float push[3], float n[3]);

/* Springs of a garment mesh: stretch (triangle edges), shear (the far vertices of two triangles
 * sharing an edge), bend (a vertex's two neighbours that lie nearly opposite). Rest lengths from
 * the panels' flat layout. */
typedef enum gar_spring_kind { GAR_STRETCH, GAR_SHEAR, GAR_BEND } gar_spring_kind;
typedef struct gar_springs {
    int n, n_stretch; /* stretch springs first */
    int32_t *ends;    /* [spring][2] */
    float *rest_m;
    uint8_t *kind;
    int32_t *vert_offset, *vert_springs; /* per vertex, the springs that touch it (CSR) */
} gar_springs;
int gar_springs_build(const gar_mesh *m, gar_springs *s);
void gar_springs_free(gar_springs *s);

/* Masses lumped from the flat triangles (kg per vertex), floored at half the mean (boundary
 * vertices). */
void gar_lump_masses(const gar_mesh *m, float density_kg_m2, float *mass);
/* skip[v] |= 1 at seam vertices, |= 2 at their stretch neighbours (cloth-cloth leaves both out:
 * the panels meet there by design). skip is zeroed by the caller. */
void gar_seam_skip(const gar_mesh *m, const gar_springs *sp, uint8_t *skip);

/* Penetration depth of points into the body mesh (signed distance < 0 inside), from the
 * nearest body vertex's triangles. */
typedef struct gar_body_sdf gar_body_sdf;
gar_body_sdf *gar_body_sdf_create(const float *xyz, int nv, const int32_t *tris, int nt);
float gar_body_sdf_eval(const gar_body_sdf *b, const float p[3]); /* metres; +1 when far */
void gar_body_sdf_destroy(gar_body_sdf *b);

/* A body as tryon's dressing sees it: any closed triangle mesh (the body model, the drape
 * test's support disc) and, optionally, cloth vertices held where they were placed. */
typedef struct gar_body_mesh {
    const float *xyz; /* [vertex][3] */
    int num_vertices;
    const int32_t *triangles; /* [triangle][3], counter-clockwise seen from outside */
    int num_triangles;
    const uint8_t *pinned; /* [cloth vertex] 1 = held (NULL = none) */
    /* [cloth vertex] 1 = held at the height it was placed at, free around the body: a fastened
     * waistband (NULL = none; gar_fastened_vertices) */
    const uint8_t *fastened;
} gar_body_mesh;
/* A fastened waistband: the vertices of the edges labelled GAR_WAIST_LABEL on torso panels (a
 * skirt's; trousers hang from the crotch too). tryon's dressing holds their height: nothing else
 * holds a skirt up, and its solver lets the contacts stretch a band over the hips (the skirt M
 * slid 13 cm down, its waist 11.6 % longer; docs/garments.md, "Placement"). [vertex] 1;
 * calloc'd, NULL when out of memory. */
#define GAR_WAIST_LABEL "waist"
uint8_t *gar_fastened_vertices(const gar_pattern *p, const gar_mesh *m);
/* tryon's dressing (dress_tryon.c) on such a body: fills st's ms, steps and seaming_s only. */
int gar_dress_tryon_on(gar_mesh *m, const gar_body_mesh *body, const gar_dress_desc *desc,
                       gar_dress_stats *st, gar_reject *why);

/* A seam is closed when every joint's partners are this close (the seam gap target: 2 mm). */
#define GAR_SEAM_CLOSED_M 0.001f

#endif
