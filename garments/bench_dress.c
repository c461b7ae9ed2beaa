/* tryon-bench-dress: dress tryon's body in sewing patterns and print the figures
 * (docs/garments.md): a table row per pattern, then one JSON line per pattern. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_dress.h"
#include "bodyfit.h"
#include "garments.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: tryon-bench-dress [options] PATTERN.json...\n"
               "Dresses tryon's body (rest pose) in each pattern and prints the figures.\n"
               "  --method seed|tryon    dressing method (default seed)\n"
               "  --collision image|bvh  cloth-body collision (default: image with seed, bvh with\n"
               "                         tryon; each method has only its own)\n"
               "  --size S|M|L           graded size (default M)\n"
               "  --fabric NAME          cotton, denim, jersey, silk (default cotton)\n"
               "  --spacing M            mesh spacing in metres (default 0.02)\n"
               "  --shape N              body shape preset 0..2 (default 0, average)\n"
               "  --cloth-cloth on|off   panel-panel repulsion (default on)\n"
               "  --iterations N         tryon's method: constraint and contact sweeps a step\n"
               "                         (default 3; more lowers the strain, costs time)\n"
               "  --spread N             tryon's method: the last rounds spreading the corners'\n"
               "                         stretch (default 100, 0 = none)\n"
               "  --obj PREFIX           write PREFIX<n>.obj, the dressed garment of pattern n\n"
               "  --strain-report        after each row: the stretch springs over the fabric's\n"
               "                         max strain, per panel, and the worst with where they lie\n"
               "  --drape                no patterns: the Cusick drape test of each fabric (or\n"
               "                         of --fabric's), a 0.30 m disc on a 0.18 m support\n"
               "  --stability            the map of seam stiffness x time step of --method on\n"
               "                         each pattern (outcome, seam gap, penetrations)\n"
               "  --pick-size            dress sizes S, M and L of each pattern on the body\n"
               "                         (--shape; tryon's method), report the fit per region,\n"
               "                         pick a size\n"
               "  --help                 this text\n");
}

typedef struct options {
    const char *method, *collision, *obj;
    gar_size size;
    const gar_fabric *fabric;
    float spacing;
    int shape, cloth_cloth, iterations, drape, pick_size, fabric_given, stability;
    int strain_report, spread;
} options;

static int need(int i, int argc, const char *opt)
{
    if (i + 1 >= argc) {
        fprintf(stderr, "tryon-bench-dress: %s needs a value (see --help)\n", opt);
        return 0;
    }
    return 1;
}

/* Returns the index of the first pattern argument, or -1 (error) / 0 (help printed). */
static int parse(int argc, char **argv, options *o)
{
    int i = 1;
    for (; i < argc && argv[i][0] == '-'; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(a, "--drape") || !strcmp(a, "--pick-size") || !strcmp(a, "--stability")) {
            *(!strcmp(a, "--drape")       ? &o->drape
              : !strcmp(a, "--pick-size") ? &o->pick_size
                                          : &o->stability) = 1;
            continue;
        }
        if (!strcmp(a, "--strain-report")) {
            o->strain_report = 1;
            continue;
        }
        if (!strcmp(a, "--method") || !strcmp(a, "--collision") || !strcmp(a, "--size") ||
            !strcmp(a, "--fabric") || !strcmp(a, "--spacing") || !strcmp(a, "--shape") ||
            !strcmp(a, "--cloth-cloth") || !strcmp(a, "--obj") || !strcmp(a, "--iterations") ||
            !strcmp(a, "--spread")) {
            if (!need(i, argc, a))
                return -1;
            const char *v = argv[++i];
            char *end = NULL;
            if (!strcmp(a, "--method"))
                o->method = v;
            else if (!strcmp(a, "--collision"))
                o->collision = v;
            else if (!strcmp(a, "--obj"))
                o->obj = v;
            else if (!strcmp(a, "--size")) {
                int s = gar_size_from_name(v);
                if (s < 0) {
                    fprintf(stderr, "tryon-bench-dress: --size %s: not S, M or L\n", v);
                    return -1;
                }
                o->size = (gar_size)s;
            } else if (!strcmp(a, "--fabric")) {
                if (!(o->fabric = gar_fabric_find(v))) {
                    fprintf(stderr, "tryon-bench-dress: --fabric %s: unknown fabric\n", v);
                    return -1;
                }
                o->fabric_given = 1;
            } else if (!strcmp(a, "--spread")) {
                long k = strtol(v, &end, 10);
                if (*end || !*v || k < 0 || k > 10000) {
                    fprintf(stderr, "tryon-bench-dress: --spread %s: not 0..10000\n", v);
                    return -1;
                }
                o->spread = k ? (int)k : -1;
            } else if (!strcmp(a, "--iterations")) {
                long k = strtol(v, &end, 10);
                if (*end || k < 1 || k > 100) {
                    fprintf(stderr, "tryon-bench-dress: --iterations %s: not 1..100\n", v);
                    return -1;
                }
                o->iterations = (int)k;
            } else if (!strcmp(a, "--spacing")) {
                o->spacing = strtof(v, &end);
                if (*end || !(o->spacing >= 0.005f && o->spacing <= 0.1f)) {
                    fprintf(stderr, "tryon-bench-dress: --spacing %s: not in [0.005, 0.1] m\n", v);
                    return -1;
                }
            } else if (!strcmp(a, "--shape")) {
                long s = strtol(v, &end, 10);
                if (*end || s < 0 || s >= FIT_SHAPE_PRESETS) {
                    fprintf(stderr, "tryon-bench-dress: --shape %s: not 0..%d\n", v,
                            FIT_SHAPE_PRESETS - 1);
                    return -1;
                }
                o->shape = (int)s;
            } else if (!strcmp(v, "on") || !strcmp(v, "off")) {
                o->cloth_cloth = !strcmp(v, "on");
            } else {
                fprintf(stderr, "tryon-bench-dress: --cloth-cloth %s: not on or off\n", v);
                return -1;
            }
            continue;
        }
        fprintf(stderr, "tryon-bench-dress: unknown option %s (see --help)\n", a);
        return -1;
    }
    if (strcmp(o->method, "seed") && strcmp(o->method, "tryon")) {
        fprintf(stderr, "tryon-bench-dress: --method %s: not seed or tryon\n", o->method);
        return -1;
    }
    int tryon = !strcmp(o->method, "tryon");
    if (!o->collision)
        o->collision = tryon ? "bvh" : "image";
    if (strcmp(o->collision, tryon ? "bvh" : "image")) {
        fprintf(stderr,
                "tryon-bench-dress: --method %s --collision %s: the seed method collides in "
                "image space, tryon's with the BVH (docs/garments.md)\n",
                o->method, o->collision);
        return -1;
    }
    if (o->drape + o->pick_size + o->stability > 1 || (o->drape && i < argc)) {
        fprintf(stderr, "tryon-bench-dress: one of --drape (no PATTERN.json), --pick-size and "
                        "--stability\n");
        return -1;
    }
    if (o->drape)
        return i;
    if (i >= argc) {
        fprintf(stderr, "tryon-bench-dress: no PATTERN.json given (see --help)\n");
        return -1;
    }
    return i;
}

static int write_obj(const gar_mesh *m, const char *prefix, int n)
{
    char path[512];
    snprintf(path, sizeof path, "%s%d.obj", prefix, n);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    for (int v = 0; v < m->num_vertices; v++)
        fprintf(f, "v %.5f %.5f %.5f\n", m->xyz[3 * v], m->xyz[3 * v + 1], m->xyz[3 * v + 2]);
    for (int t = 0; t < m->num_triangles; t++)
        fprintf(f, "f %d %d %d\n", m->triangles[3 * t] + 1, m->triangles[3 * t + 1] + 1,
                m->triangles[3 * t + 2] + 1);
    return fclose(f);
}

/* One pattern: load, grade, mesh, place, dress, print the row; fills st. */
static int run(const char *path, const options *o, const fit_model *body, int n,
               gar_dress_stats *st, int *verts)
{
    gar_pattern p;
    gar_mesh m = {0};
    gar_reject why = {0};
    int rc = gar_pattern_load(path, &p, &why);
    if (!rc) {
        gar_pattern_grade(&p, o->size);
        rc = gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = o->spacing}, &m, &why);
    }
    if (!rc)
        rc = gar_mesh_place(&p, &m, body, NULL, NULL, NULL, &why);
    if (!rc) {
        gar_dress_desc d = {.fabric = o->fabric,
                            .cloth_cloth = o->cloth_cloth,
                            .iterations = o->iterations,
                            .spread_rounds = o->spread};
        rc = !strcmp(o->method, "tryon") ? gar_dress_tryon(&p, &m, body, &d, st, &why)
                                         : gar_dress_seed(&p, &m, body, &d, st, &why);
    }
    if (rc)
        fprintf(stderr, "tryon-bench-dress: %s: %s: %s (skipped)\n", path, gar_error_name(rc),
                why.detail);
    else if (o->obj && write_obj(&m, o->obj, n))
        fprintf(stderr, "tryon-bench-dress: cannot write %s%d.obj\n", o->obj, n);
    if (!rc && o->strain_report && gar_strain_report(&p, &m, body, o->fabric->max_strain, stdout))
        fprintf(stderr, "tryon-bench-dress: %s: strain report: out of memory\n", path);
    *verts = m.num_vertices;
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    return rc;
}

int main(int argc, char **argv)
{
    options o = {"seed", NULL, NULL, GAR_SIZE_M, NULL, 0.02f, 0, 1, 0, 0, 0, 0, 0, 0, 0};
    o.fabric = gar_fabric_find("cotton");
    int first = parse(argc, argv, &o);
    if (first <= 0)
        return first == 0 ? 0 : 2;
    if (o.drape)
        return bench_drape(o.fabric_given ? o.fabric : NULL, o.iterations);
    char err[200];
    fit_model *body = fit_model_create(
        &(fit_model_desc){.shape = fit_shape_preset(o.shape), .target_vertices = 10000}, err,
        sizeof err);
    if (!body) {
        fprintf(stderr, "tryon-bench-dress: body: %s\n", err);
        return 1;
    }
    int n = argc - first, failed = 0;
    gar_dress_stats *st = calloc((size_t)n, sizeof *st);
    int *verts = calloc((size_t)n, sizeof *verts), *ok = calloc((size_t)n, sizeof *ok);
    if (!st || !verts || !ok) {
        fprintf(stderr, "tryon-bench-dress: out of memory\n");
        return 1;
    }
    if (o.stability) {
        gar_dress_desc dd = {
            .fabric = o.fabric, .cloth_cloth = o.cloth_cloth, .iterations = o.iterations};
        for (int i = 0; i < n; i++)
            failed += bench_stability(argv[first + i], body, !strcmp(o.method, "tryon"),
                                      &(gar_mesh_desc){.spacing_m = o.spacing}, &dd);
        free(st), free(verts), free(ok);
        fit_model_destroy(body);
        return failed ? 1 : 0;
    }
    if (o.pick_size) {
        gar_dress_desc dd = {
            .fabric = o.fabric, .cloth_cloth = o.cloth_cloth, .iterations = o.iterations};
        for (int i = 0; i < n; i++)
            failed += bench_pick_size(argv[first + i], body, o.shape,
                                      &(gar_mesh_desc){.spacing_m = o.spacing}, &dd);
        free(st), free(verts), free(ok);
        fit_model_destroy(body);
        return failed ? 1 : 0;
    }
    printf("%-28s %8s %8s %8s %6s %8s %8s %6s %6s %4s\n", "pattern", "ms", "seam_mm", "seamed_s",
           "pen", "max_str", "p99_str", "cross", "verts", "thr");
    for (int i = 0; i < n; i++) {
        ok[i] = !run(argv[first + i], &o, body, i, &st[i], &verts[i]);
        failed += !ok[i];
        const char *base = strrchr(argv[first + i], '/');
        if (ok[i])
            printf("%-28.28s %8.0f %8.2f %8.3f %6d %8.4f %8.4f %6d %6d %4d\n",
                   base ? base + 1 : argv[first + i], st[i].ms, st[i].seam_gap_mm, st[i].seaming_s,
                   st[i].penetrating, st[i].max_strain, st[i].p99_strain, st[i].crossings, verts[i],
                   st[i].threads);
    }
    for (int i = 0; i < n; i++)
        if (ok[i])
            printf("{\"pattern\": \"%s\", \"method\": \"%s\", \"collision\": \"%s\", \"size\": "
                   "\"%c\", \"fabric\": \"%s\", \"ms\": %.1f, \"seam_gap_mm\": %.3f, "
                   "\"penetrating\": %d, \"max_pen_mm\": %.2f, \"max_strain\": %.4f, "
                   "\"p99_strain\": %.4f, \"crossings\": %d, \"verts\": %d, \"threads\": %d}\n",
                   argv[first + i], o.method, o.collision, "SML"[o.size], o.fabric->name, st[i].ms,
                   st[i].seam_gap_mm, st[i].penetrating, st[i].max_pen_mm, st[i].max_strain,
                   st[i].p99_strain, st[i].crossings, verts[i], st[i].threads);
    free(st), free(verts), free(ok);
    fit_model_destroy(body);
    return failed ? 1 : 0;
}
