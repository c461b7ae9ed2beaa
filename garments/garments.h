/* garments: sewing patterns (GarmentCode / Korosteleva JSON), their panels meshed and their
 * seams sampled into joints, and the fabric presets. Used by the sim and the mirror.
 *
 * Units: everything read is converted to metres (panel frame: u right, v up, as in the file;
 * world frame: metres, y up, as bodyfit.h). The caller owns what it passes; every create or
 * load has a free that accepts NULL or a zeroed struct. */
#ifndef TRYON_GARMENTS_H
#define TRYON_GARMENTS_H

#include <stddef.h>
#include <stdint.h>

/* Why a pattern or a mesh was refused (STYLE.md 11). */
#define GAR_ERROR_LIST(X)                                                                          \
    X(GAR_OK, "ok")                                                                                \
    X(GAR_ERR_ARG, "bad argument")                                                                 \
    X(GAR_ERR_NO_MEMORY, "out of memory")                                                          \
    X(GAR_ERR_IO, "cannot read the file")                                                          \
    X(GAR_ERR_JSON, "not valid JSON")                                                              \
    X(GAR_ERR_MISSING, "required field missing")                                                   \
    X(GAR_ERR_TYPE, "field has the wrong type")                                                    \
    X(GAR_ERR_RANGE, "value out of range or not finite")                                           \
    X(GAR_ERR_CURVE, "edge curvature malformed")                                                   \
    X(GAR_ERR_OUTLINE, "panel outline not a simple closed loop")                                   \
    X(GAR_ERR_STITCH, "stitch names a missing panel or edge")                                      \
    X(GAR_ERR_TOO_LARGE, "more panels, vertices or samples than allowed")                          \
    X(GAR_ERR_MESH, "panel could not be meshed with its outline kept")

#define GAR_ERROR_ENUM(id, text) id,
typedef enum gar_error { GAR_ERROR_LIST(GAR_ERROR_ENUM) GAR_ERROR_COUNT } gar_error;
#undef GAR_ERROR_ENUM
/* Functions return 0 or -GAR_ERR_x. */
const char *gar_error_name(int e); /* "GAR_ERR_CURVE"; accepts e or -e */
const char *gar_error_text(int e);

typedef struct gar_reject {
    gar_error code;
    char detail[200]; /* where: "panel 'front': edge 3: circle radius -2 not positive" */
} gar_reject;

/* Limits on what a file may ask for (the data sets' largest patterns have ~40 panels of
 * under 100 edges); coordinates and radii beyond GAR_MAX_COORD_M are refused. */
#define GAR_MAX_PANELS         128
#define GAR_MAX_PANEL_VERTICES 256
#define GAR_MAX_STITCHES       1024
#define GAR_NAME_LEN           64
#define GAR_MAX_COORD_M        100.0

typedef enum gar_curve { GAR_LINE, GAR_QUADRATIC, GAR_CUBIC, GAR_CIRCLE } gar_curve;

/* One edge. Control points are absolute, in the panel frame (metres), already converted from
 * the file's relative encoding. Circle: an SVG arc; right = 1 bulges to the right of start->end
 * (GarmentCode's "right"), a radius below half the chord is raised to it (as SVG does). */
typedef struct gar_edge {
    int v0, v1;
    gar_curve kind;
    float ctrl[2][2];
    float radius_m;
    int large_arc, right;
    char label[GAR_NAME_LEN];
} gar_edge;

typedef struct gar_panel {
    char name[GAR_NAME_LEN];
    int num_vertices;
    float *uv_m; /* [vertex][2] */
    int num_edges;
    gar_edge *edges;        /* edge k runs from vertex edges[k].v0 to edges[k].v1, ccw */
    float translation_m[3]; /* world = R [u, v, 0] + translation */
    float rotation_deg[3];  /* Euler XYZ degrees, R = Rz Ry Rx */
} gar_panel;

typedef struct gar_stitch {
    int panel[2], edge[2]; /* edge a at fraction t meets edge b at fraction 1 - t */
} gar_stitch;

typedef struct gar_pattern {
    int num_panels;
    gar_panel *panels; /* in panel_order when the file gives one, else in file order */
    int num_stitches;
    gar_stitch *stitches;
    float units_in_meter; /* as read: 100 = the file is in centimetres */
} gar_pattern;

/* Reading. json need not be NUL-terminated. Everything in the file is untrusted: a refusal
 * names the panel, edge or stitch at fault in why->detail. */
int gar_pattern_parse(const char *json, size_t len, gar_pattern *out, gar_reject *why);
int gar_pattern_load(const char *path, gar_pattern *out, gar_reject *why);
void gar_pattern_free(gar_pattern *p);
int gar_pattern_find_panel(const gar_pattern *p, const char *name); /* -1 if none */

/* Geometry of one edge. t in [0, 1] is the curve parameter (not arc length). */
void gar_edge_eval(const gar_panel *panel, const gar_edge *e, float t, float out_uv[2]);
float gar_edge_length(const gar_panel *panel, const gar_edge *e); /* metres */
/* n + 1 points at equal arc-length steps, first = start vertex, last = end vertex. */
int gar_edge_sample(const gar_panel *panel, const gar_edge *e, int n, float *out_uv);
/* R [u, v, 0] + translation, R = Rz Ry Rx from the panel's Euler degrees. */
void gar_panel_to_world(const gar_panel *panel, const float uv[2], float out_xyz[3]);

/* Sizes graded from one base (the shipped files are size M): horizontal (girth) and vertical
 * (length) scale about each panel's origin, placements scaled alike. */
typedef enum gar_size { GAR_SIZE_S = 0, GAR_SIZE_M = 1, GAR_SIZE_L = 2 } gar_size;
int gar_size_from_name(const char *name); /* "S", "M", "L" (any case); -1 if unknown */
void gar_pattern_grade(gar_pattern *p, gar_size size);

/* Meshing: each panel's outline sampled every spacing_m (stitched edges of about equal length
 * get equal counts so their joints pair point to point), interior points on the seed's
 * rectangular grid, Delaunay-triangulated and clipped to the outline. */
typedef struct gar_mesh_desc {
    float spacing_m; /* 0 = 0.02 */
} gar_mesh_desc;

/* A joint pulls vertex a to its partner (1 - w) x[b0] + w x[b1] (seed: point-point when
 * w == 0, point-edge otherwise; gathers give point-edge joints). */
typedef struct gar_joint {
    int32_t a, b0, b1;
    float w;
    int32_t stitch;
} gar_joint;

typedef struct gar_mesh {
    int num_vertices;
    float *uv_m;       /* [vertex][2] rest position in its panel, metres */
    float *xyz;        /* [vertex][3] world position from the file's placement */
    int32_t *panel_of; /* [vertex] */
    int num_triangles;
    int32_t *triangles; /* [triangle][3], ccw in the panel frame (front normal = +w) */
    int num_panels;
    int32_t *panel_first_edge; /* [panel] index into the flat edge list below */
    int num_edges;             /* all panels' edges, flat */
    int32_t *edge_offset;      /* [num_edges + 1] into edge_vertices */
    int32_t *edge_vertices;    /* boundary vertices along each edge, start to end inclusive */
    int num_joints;
    gar_joint *joints;
} gar_mesh;

int gar_mesh_build(const gar_pattern *p, const gar_mesh_desc *desc, gar_mesh *out, gar_reject *why);
void gar_mesh_free(gar_mesh *m);

/* Placement around tryon's body (place.c). Each panel is classed by where the file puts it
 * (on the reference body: bodyfit's average shape) and wrapped, unstretched along u, on a
 * surface of revolution around that part of the given body (axes from its joints), a
 * clearance outside the body's widest point at each level, facing as the file faces it. */
typedef enum gar_part {
    GAR_PART_TORSO,
    GAR_PART_ARM_L,
    GAR_PART_ARM_R,
    GAR_PART_LEG_L,
    GAR_PART_LEG_R,
    GAR_PART_COUNT
} gar_part;
gar_part gar_panel_part(const gar_pattern *p, int panel);

typedef struct gar_place_desc {
    float clearance_m; /* 0 = 0.02 */
} gar_place_desc;
struct fit_model;
/* Rewrites m->xyz. body_xyz / joints: a posed body (NULL = the rest pose). */
int gar_mesh_place(const gar_pattern *p, gar_mesh *m, const struct fit_model *body,
                   const float *body_xyz, const float *joints, const gar_place_desc *desc,
                   gar_reject *why);

/* The seed's dressing (seed 003; dress_seed.c): a mass-spring cloth (stretch, shear and bend
 * springs, viscous damping, gravity) stitched by joint forces, over-elongated springs corrected
 * in velocity (Vassilev), the six parallel loops of the seed's Algorithm 1 under OpenMP,
 * cloth-body collision in image space (front and back orthographic depth and normal maps of the
 * body, rendered on the CPU), cloth-cloth between panels by the recursive AABB split in four
 * (OpenMP tasks); seaming until the seams close, then draping steps. */
typedef struct gar_dress_desc {
    const struct gar_fabric *fabric; /* NULL = cotton */
    float dt_s;                      /* 0 = 0.001 */
    float max_seaming_s;             /* simulated time allowed to close the seams; 0 = 2 */
    int drape_steps;                 /* after the seams close; 0 = 300 */
    float map_pixel_m;               /* depth map pixel; 0 = 0.004 */
    int cloth_cloth;                 /* 1 = panel-panel repulsion on */
    int iterations; /* tryon's method: sweeps of constraints and contacts a step; 0 = 3 while
                     * seaming, 8 once gravity is on */
    /* Seam stiffness as a multiple of the fabric's stretch stiffness: the seed's joint springs
     * (0 = 1, its default), tryon's seams as XPBD constraints of that stiffness (0 = hard, its
     * default). The stability map's axis (docs/garments.md). */
    float seam_gain;
    /* tryon's method: the last rounds of strain limit, seams and contacts that spread the
     * corners' stretch along their edges (0 = 100, < 0 = none; docs/garments.md, "Strain") */
    int spread_rounds;
} gar_dress_desc;

/* The figures of a dressed garment (ARCHITECTURE.md "Metrics"). */
typedef struct gar_dress_stats {
    float ms;          /* wall clock of the whole dressing */
    int steps;         /* integration steps, seaming and draping */
    float seaming_s;   /* simulated time until every joint was within GAR_SEAM_CLOSED_M */
    float seam_gap_mm; /* max distance between joint partners */
    int penetrating;   /* vertices more than 1 mm inside the body */
    float max_pen_mm;
    float max_strain, p99_strain; /* stretch springs */
    int crossings;                /* edges of one panel through a triangle of another */
    int threads;
} gar_dress_stats;

/* Dresses m (its xyz placed: gar_mesh_place) on the body in its rest pose. */
int gar_dress_seed(const gar_pattern *p, gar_mesh *m, const struct fit_model *body,
                   const gar_dress_desc *desc, gar_dress_stats *stats, gar_reject *why);
/* Cloth kept this far outside the body by tryon's dressing (the penetration metric allows 1 mm
 * inside); the sim wearing a dressed pattern keeps the same, or its contacts push the cloth out
 * by the difference where it lies on the body and stretch it round the arms (sim/outfit_pattern.h,
 * docs/garments.md "Pattern garments on the moving body"). */
#define GAR_TRYON_THICKNESS_M 0.003f
/* tryon's own dressing (dress_tryon.c): sim/'s XPBD in small steps (desc->dt_s, 0 = 2 ms),
 * the seams as zero-length constraints closed progressively (no gravity), exact cloth-body
 * contacts from sim/'s BVH, then desc->drape_steps (0 = 150) with gravity. max_seaming_s:
 * 0 = 1 s; map_pixel_m is not used. */
int gar_dress_tryon(const gar_pattern *p, gar_mesh *m, const struct fit_model *body,
                    const gar_dress_desc *desc, gar_dress_stats *stats, gar_reject *why);
/* The figures alone, of any state of the mesh (xyz) on the rest body. */
int gar_dress_measure(const gar_mesh *m, const struct fit_model *body, gar_dress_stats *stats);

/* Fit of a dressed garment per body region (fit.c): each garment vertex belongs to the region
 * of the body under it (the strongest skinning joint of the nearest body vertex, within 10 cm). */
#define GAR_REGION_LIST(X)                                                                         \
    X(GAR_REGION_SHOULDERS, "shoulders")                                                           \
    X(GAR_REGION_CHEST, "chest")                                                                   \
    X(GAR_REGION_WAIST, "waist")                                                                   \
    X(GAR_REGION_HIPS, "hips")                                                                     \
    X(GAR_REGION_THIGHS, "thighs")                                                                 \
    X(GAR_REGION_LOWER_LEGS, "lower_legs")                                                         \
    X(GAR_REGION_ARMS, "arms")
#define GAR_REGION_ENUM(id, name) id,
typedef enum gar_region { GAR_REGION_LIST(GAR_REGION_ENUM) GAR_REGION_COUNT } gar_region;
#undef GAR_REGION_ENUM
const char *gar_region_name(gar_region r);
typedef struct gar_fit_region {
    int vertices;                 /* garment vertices over the region */
    float max_strain, p95_strain; /* stretch springs starting there */
    float contact;                /* share of its vertices within 5 mm of the body: the pressure */
    float gap_mm;                 /* median distance to the body */
} gar_fit_region;
typedef struct gar_fit {
    gar_fit_region region[GAR_REGION_COUNT];
} gar_fit;
/* m dressed on body (rest pose). */
int gar_fit_measure(const gar_mesh *m, const struct fit_model *body, gar_fit *out);

/* Which size fits (pick_size.c): the pattern at path dressed in S, M and L on body with tryon's
 * method; the pick is the smallest size whose every region's p95 strain is within limit (the
 * fabric's max_strain times GAR_PICK_TIGHT_FACTOR), else the least tight size. */
#define GAR_PICK_TIGHT_FACTOR 2.0f
typedef struct gar_size_pick {
    gar_size size; /* the pick */
    char reason[240];
    float limit;    /* strain a region may have */
    int dressed[3]; /* per size, as gar_size */
    gar_dress_stats stats[3];
    gar_fit fit[3];
    float tight[3];      /* the tightest region's p95 strain */
    int tight_region[3]; /* which (gar_region; -1 none) */
    float loose_mm[3];   /* mean over the covered regions of their median gap */
} gar_size_pick;
int gar_pick_size(const char *path, const struct fit_model *body, const gar_mesh_desc *mesh,
                  const gar_dress_desc *dress, gar_size_pick *out, gar_reject *why);

/* The Cusick drape test (drape.c): a disc of the fabric, specimen_d_m across, clamped centred on
 * a support disc support_d_m across (BS 5058: 0.30 m on 0.18 m), hangs under its own weight
 * (tryon's dressing, 2 ms steps); then the area of its shadow seen from above. */
typedef struct gar_drape_desc {
    const struct gar_fabric *fabric; /* NULL = cotton */
    float specimen_d_m;              /* 0 = 0.30 */
    float support_d_m;               /* 0 = 0.18 */
    float spacing_m;                 /* mesh spacing; 0 = 0.01 */
    int steps;                       /* hanging steps of 2 ms; 0 = 1000 */
    int iterations;                  /* as gar_dress_desc; 0 = its default */
} gar_drape_desc;
typedef struct gar_drape_result {
    float coefficient; /* (shadow - support) / (specimen - support): 1 flat, 0 straight down */
    float shadow_m2;   /* projected area, support included */
    float drop_m;      /* how far the lowest point hangs below the support */
    float ms;          /* wall clock of the hanging */
    int vertices;
} gar_drape_result;
int gar_drape_test(const gar_drape_desc *desc, gar_drape_result *out, gar_reject *why);

/* Fabrics: one table (fabric.c). Membrane stiffnesses in N/m as sim_fabric. */
typedef struct gar_fabric {
    const char *name;
    float density_kg_m2;
    float stretch_n_m;
    float shear_n_m;
    float bend_n_m;
    float friction;          /* cloth-body Coulomb coefficient */
    float max_strain;        /* elongation the seed's velocity correction allows, fraction */
    float bend_rigidity_n_m; /* bending rigidity B (N m = N m^2 / m), tryon's bending */
} gar_fabric;
int gar_fabric_count(void);
const gar_fabric *gar_fabric_get(int i);
const gar_fabric *gar_fabric_find(const char *name); /* NULL if unknown */

#endif
