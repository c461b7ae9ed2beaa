/* tryon-bench-dress --drape (docs/garments.md, "Drape test"): each fabric preset's Cusick drape
 * coefficient against the band measured on real fabrics of its kind. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench_dress.h"

/* Published Cusick drape coefficients (30 cm specimen on an 18 cm support) for fabrics of each
 * preset's kind; sources in docs/garments.md. */
static const struct band {
    const char *fabric;
    float lo, hi;
} bands[] = {{"cotton", 0.45f, 0.75f},
             {"denim", 0.70f, 0.95f},
             {"jersey", 0.25f, 0.50f},
             {"silk", 0.20f, 0.45f}};

static const struct band *band_of(const char *name)
{
    for (size_t i = 0; i < sizeof bands / sizeof bands[0]; i++)
        if (!strcmp(bands[i].fabric, name))
            return &bands[i];
    return NULL;
}

int bench_drape(const gar_fabric *only, int iterations)
{
    int failed = 0;
    printf("%-8s %8s %10s %8s %8s %8s %6s\n", "fabric", "drape_c", "band", "in_band", "drop_mm",
           "ms", "verts");
    for (int i = 0; i < gar_fabric_count(); i++) {
        const gar_fabric *f = gar_fabric_get(i);
        if (only && only != f)
            continue;
        gar_drape_result r;
        gar_reject why = {0};
        if (gar_drape_test(&(gar_drape_desc){.fabric = f, .iterations = iterations}, &r, &why)) {
            fprintf(stderr, "tryon-bench-dress: --drape %s: %s\n", f->name, why.detail);
            failed = 1;
            continue;
        }
        const struct band *b = band_of(f->name);
        int in = b && r.coefficient >= b->lo && r.coefficient <= b->hi;
        printf("%-8s %8.3f %4.2f-%4.2f %8s %8.1f %8.0f %6d\n", f->name, r.coefficient,
               b ? b->lo : 0, b ? b->hi : 0, b ? (in ? "yes" : "no") : "-", r.drop_m * 1e3f, r.ms,
               r.vertices);
        printf("{\"fabric\": \"%s\", \"drape_coefficient\": %.4f, \"band\": [%.2f, %.2f], "
               "\"in_band\": %s, \"drop_mm\": %.1f, \"ms\": %.1f, \"verts\": %d}\n",
               f->name, r.coefficient, b ? b->lo : 0, b ? b->hi : 0, in ? "true" : "false",
               r.drop_m * 1e3f, r.ms, r.vertices);
    }
    return failed;
}

/* --pick-size: one pattern in S, M and L on the body, its fit per region and the pick. */
int bench_pick_size(const char *path, const struct fit_model *body, int shape,
                    const gar_mesh_desc *md, const gar_dress_desc *dd)
{
    gar_size_pick pk;
    gar_reject why = {0};
    if (gar_pick_size(path, body, md, dd, &pk, &why)) {
        fprintf(stderr, "tryon-bench-dress: --pick-size %s: %s\n", path, why.detail);
        return 1;
    }
    printf("== %s on body shape %d\n%-4s %-11s %7s %7s %7s %7s %7s\n", path, shape, "size",
           "region", "verts", "max_str", "p95_str", "contact", "gap_mm");
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s++)
        for (int r = 0; r < GAR_REGION_COUNT; r++) {
            const gar_fit_region *f = &pk.fit[s].region[r];
            if (f->vertices)
                printf("%-4c %-11s %7d %7.3f %7.3f %7.2f %7.1f\n", "SML"[s],
                       gar_region_name((gar_region)r), f -> vertices, f -> max_strain,
                       f -> p95_strain, f -> contact, f -> gap_mm);
        }
    printf("pick: %s\n", pk.reason);
    printf("{\"pattern\": \"%s\", \"shape\": %d, \"pick\": \"%c\", \"limit\": %.3f", path, shape,
           "SML"[pk.size], pk.limit);
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s++)
        printf(", \"%c\": {\"tight\": %.4f, \"tight_region\": \"%s\", \"gap_mm\": %.1f, "
               "\"max_strain\": %.4f, \"p99_strain\": %.4f, \"penetrating\": %d, \"ms\": %.0f}",
               "SML"[s], pk.tight[s],
               pk.tight_region[s] >= 0 ? gar_region_name((gar_region)pk.tight_region[s]) : "none",
               pk.loose_mm[s], pk.stats[s].max_strain, pk.stats[s].p99_strain,
               pk.stats[s].penetrating, pk.stats[s].ms);
    printf("}\n");
    return 0;
}

/* What became of one dressing: it blew up (a coordinate not finite or beyond 3 m, or a spring
 * stretched over 5 times), left a seam open (> 2 mm) or closed. */
static const char *outcome(const gar_mesh *m, const gar_dress_stats *st)
{
    for (int i = 0; i < 3 * m->num_vertices; i++)
        if (!isfinite(m->xyz[i]) || fabsf(m->xyz[i]) > 3.0f)
            return "blew";
    if (!(st->max_strain < 5.0f))
        return "blew";
    return st->seam_gap_mm > 2.0f ? "open" : "ok";
}

static int stability_cell(const char *path, const struct fit_model *body, int tryon,
                          const gar_mesh_desc *md, gar_dress_desc *dd, const char **what,
                          gar_dress_stats *st)
{
    gar_pattern p;
    gar_mesh m = {0};
    gar_reject why = {0};
    int rc = gar_pattern_load(path, &p, &why);
    if (!rc)
        rc = gar_mesh_build(&p, md, &m, &why);
    if (!rc)
        rc = gar_mesh_place(&p, &m, body, NULL, NULL, NULL, &why);
    if (!rc)
        rc = tryon ? gar_dress_tryon(&p, &m, body, dd, st, &why)
                   : gar_dress_seed(&p, &m, body, dd, st, &why);
    if (rc)
        fprintf(stderr, "tryon-bench-dress: --stability %s: %s\n", path, why.detail);
    else
        *what = outcome(&m, st);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    return rc;
}

int bench_stability(const char *path, const struct fit_model *body, int tryon,
                    const gar_mesh_desc *md, const gar_dress_desc *base)
{
    /* seam stiffness (times the fabric's stretch stiffness; tryon's 0: hard seams) x step */
    enum { NG = 5, NS = 4 };
    static const float gains[NG] = {0, 0.1f, 1, 10, 100};
    static const float steps_ms[NS] = {0.5f, 1, 2, 4};
    const char *what[NG][NS] = {{0}};
    gar_dress_stats st[NG][NS];
    memset(st, 0, sizeof st);
    printf("== %s, method %s: seam gain x step (ms); cell: outcome, seam gap mm, penetrating\n"
           "%-6s",
           path, tryon ? "tryon" : "seed", "gain");
    for (int j = 0; j < NS; j++)
        printf(" %18.1f", steps_ms[j]);
    printf("\n");
    int failed = 0;
    for (int i = tryon ? 0 : 1; i < NG; i++) {
        if (gains[i] > 0)
            printf("%-6g", gains[i]);
        else
            printf("%-6s", "hard");
        for (int j = 0; j < NS; j++) {
            gar_dress_desc dd = *base;
            dd.seam_gain = gains[i], dd.dt_s = steps_ms[j] * 1e-3f;
            what[i][j] = "error";
            failed |= stability_cell(path, body, tryon, md, &dd, &what[i][j], &st[i][j]);
            if (strcmp(what[i][j], "blew"))
                printf(" %6s %6.1f %4d", what[i][j], st[i][j].seam_gap_mm, st[i][j].penetrating);
            else /* the figures of a garment that blew up mean nothing */
                printf(" %6s %6s %4s", what[i][j], "-", "-");
            fflush(stdout);
        }
        printf("\n");
    }
    for (int i = tryon ? 0 : 1; i < NG; i++)
        for (int j = 0; j < NS; j++)
            printf("{\"pattern\": \"%s\", \"method\": \"%s\", \"seam_gain\": %g, \"dt_ms\": %g, "
                   "\"outcome\": \"%s\", \"seam_gap_mm\": %.2f, \"penetrating\": %d, "
                   "\"max_strain\": %.3f, \"ms\": %.0f}\n",
                   path, tryon ? "tryon" : "seed", gains[i], steps_ms[j], what[i][j],
                   st[i][j].seam_gap_mm, st[i][j].penetrating, st[i][j].max_strain, st[i][j].ms);
    return failed;
}
