/* tryon-bench-sim: a garment on a body (or the drape sheet on a sphere), timed per frame; a
 * human table per group of frames, then one JSON line. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "collide.h"
#include "collide_bvh.h"
#include "scene.h"
#include "sim.h"
#ifdef BENCH_HAVE_PATTERN
#include "bench_pattern.h"
#include "outfit_pattern.h"
#endif

#define BENCH_SETTLE_FRAMES  30  /* strain and error are judged after the first second */
#define BENCH_REF_EVERY      10  /* the reference keeps every tenth frame */
#define BENCH_REF_ITERATIONS 200 /* the reference (docs/sim.md: the convergence study) */
/* The body scene's body detail: the body model at 6,000 vertices is 0.74 mm RMS from the same
 * body at 30,000 where the camera knows the body to about a centimetre, and the shirt on it is as
 * near the reference on the 10,000-vertex body as on its own (docs/sim.md, "Body detail and
 * the shape error"). */
#define BENCH_BODY_VERTS 6000
#define BENCH_LIMB_EVERY 5 /* a pattern's limb check (bench_pattern.h), every 5th frame */
/* In the reference cache's file names: raise it with every change to the solver's results or to
 * the scenes' motions, so that no reference of another model is reused. */
#define BENCH_REF_VERSION 9

typedef struct bench_opts {
    const char *scene, *motion, *csv, *cache_dir;
    int verts, body_verts, ref_body_verts, iterations, frames, group, ref_iterations, compare_ref;
    sim_desc desc;
    int no_ref, window_ref, window_frames;
    float hem_m; /* the shirt's hem below the pelvis joint (sim_garment_shirt; 0: its default) */
    /* --garment PATTERN.json [--size] [--fabric] (bench_pattern.h): worn instead of the shirt */
    const char *garment, *fabric;
    int size;
    struct bench_pattern *pattern; /* dressed once in main */
} bench_opts;

typedef struct bench_run {
    float *ms; /* per frame */
    sim_frame_stats *st;
    float *snap; /* frames / BENCH_REF_EVERY snapshots of nv * 3 */
    float *vel;  /* the velocities (m/s) at the same frames */
    /* --window-ref, the measured run: its positions and velocities --window-frames frames before
     * each snapshot, where the windowed references start */
    float *start_x, *start_v;
    int nv, nsnap, diverged_frames;
    int body_nv; /* the body's vertices (the sphere's for the drape) */
    char device[96];
    /* a pattern garment: the fraction of its limb panels' vertices near their limbs, after the
       settling frames (worst frame) and on the first frame (-1: no such panels) */
    float arm_near_min, leg_near_min, arm_near_first, leg_near_first;
} bench_run;

/* The machine's CPU ticks so far, all and stolen (by the hypervisor: a virtual machine's cores
 * given to another guest), from /proc/stat's first line; -1 where it cannot be read. */
static int cpu_ticks(unsigned long long *total, unsigned long long *steal)
{
    unsigned long long v[8] = {0};
    FILE *f = fopen("/proc/stat", "r");
    int n = f ? fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3],
                       &v[4], &v[5], &v[6], &v[7])
              : 0;
    if (f)
        fclose(f);
    if (n < 8)
        return -1;
    *total = v[0] + v[1] + v[2] + v[3] + v[4] + v[5] + v[6] + v[7];
    *steal = v[7];
    return 0;
}

static void usage(FILE *f)
{
    fprintf(
        f,
        "usage: tryon-bench-sim [--scene drape|body] [--verts N] [--iterations K] "
        "[--frames F]\n"
        "         [--body-verts N (body model, default %d; 0 = the model's own default)]\n"
        "         [--hem M (the shirt's hem below the pelvis joint; 0: 0.12 m, at the hips)]\n"
        "         [--ref-body-verts N (the references' body model, 0 = the run's)]\n"
        "         [--backend c|opencl] [--solver seed|tryon]\n"
        "         [--motion all|NAME|FILE.bvh|FILE.lcmlog (a session's bodies, tryon run "
        "--record)]\n"
        "         [--stretch N/m] [--bend N/m] [--follow F (0..1; < 0: world frame)]\n"
        "         [--friction MU (< 0: none)] [--damping D (per second, < 0: none)]\n"
        "         [--thickness M (contacts; default 0.004, a --garment the dressing's 0.003)]\n"
        "         [--garment PATTERN.json [--size S|M|L] [--fabric NAME] (body scene: a sewing\n"
        "          pattern dressed on the body instead of the shirt, meshed to about --verts)]\n"
        "         [--support 0|-1 (garments without attachments: the support hierarchy on|off)]\n"
        "         [--strain-limit S (the clamp, default 0.0075)]\n"
        "         [--strain-retry 0|-1 (frames over 3 %% max / 1 %% p99 strain redone: on|off)]\n"
        "         [--retry-budget MS (those retries only within MS a frame; 0: no budget)]\n"
        "         [--csv FILE] [--cache-dir DIR (default $TRYON_CACHE_DIR, $XDG_CACHE_HOME/tryon\n"
        "          or ~/.cache/tryon)] [--no-ref]\n"
        "         [--ref-iterations N (default %d)] [--compare-ref M] [--window-ref]\n"
        "         [--window-frames W (1..%d)]\n"
        "--window-ref: also the error to references restarted from the run's own state\n"
        "              W frames (default %d) before every snapshot (every %d frames; not cached)\n"
        "--compare-ref M: only the RMS (mm) between the references of N and M iterations,\n"
        "                 in all and per motion (each computed once into the cache)\n",
        BENCH_BODY_VERTS, BENCH_REF_ITERATIONS, BENCH_REF_EVERY, BENCH_REF_EVERY, BENCH_REF_EVERY);
}

/* The reference caches live in the user's cache directory, never in the current one (a run
 * from the repository would leave untracked files): $TRYON_CACHE_DIR, else
 * $XDG_CACHE_HOME/tryon, else $HOME/.cache/tryon; --cache-dir overrides all. */
static const char *default_cache_dir(void)
{
    static char dir[512];
    const char *env = getenv("TRYON_CACHE_DIR"), *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");
    if (env && env[0])
        snprintf(dir, sizeof dir, "%s", env);
    else if (xdg && xdg[0] == '/')
        snprintf(dir, sizeof dir, "%s/tryon", xdg);
    else if (home && home[0] == '/')
        snprintf(dir, sizeof dir, "%s/.cache/tryon", home);
    else
        return NULL;
    return dir;
}

/* mkdir -p: every missing parent of dir, then dir. Returns 0 when dir exists afterwards. */
static int make_dirs(const char *dir)
{
    char p[512];
    snprintf(p, sizeof p, "%s", dir);
    for (char *c = p + 1; *c; c++)
        if (*c == '/') {
            *c = 0;
            mkdir(p, 0755);
            *c = '/';
        }
    mkdir(p, 0755);
    struct stat st;
    return stat(p, &st) == 0 && S_ISDIR(st.st_mode) ? 0 : -1;
}

/* --garment: the pattern's fabric for the sim (--stretch and --bend still override it). */
static int pattern_fabric(bench_opts *o, int body)
{
    if (!o->garment && !o->fabric)
        return 0;
    if (!body || !o->garment) {
        fprintf(stderr,
                "tryon-bench-sim: --garment PATTERN.json (and --fabric) need --scene body\n");
        return -1;
    }
#ifdef BENCH_HAVE_PATTERN
    sim_fabric f, given = o->desc.fabric, dflt = sim_default_desc().fabric;
    char err[300] = "";
    bench_pattern_desc d = {.path = o->garment, .size = (sim_size)o->size, .fabric = o->fabric};
    if (bench_pattern_fabric(&d, &f, err, sizeof err) < 0) {
        fprintf(stderr, "tryon-bench-sim: %s\n", err);
        return -1;
    }
    if (given.stretch_n_m != dflt.stretch_n_m)
        f.stretch_n_m = given.stretch_n_m;
    if (given.bend_n_m != dflt.bend_n_m)
        f.bend_n_m = given.bend_n_m;
    o->desc.fabric = f;
    if (o->desc.thickness_m == sim_default_desc().thickness_m) /* unless --thickness */
        o->desc.thickness_m = sim_pattern_thickness_m();
    return 0;
#else
    fprintf(stderr, "tryon-bench-sim: built without garments/: no --garment\n");
    return -1;
#endif
}

static int parse(int argc, char **argv, bench_opts *o)
{
    *o = (bench_opts){.scene = "drape",
                      .motion = "all",
                      .verts = 7056,
                      .body_verts = BENCH_BODY_VERTS,
                      .iterations = 25,
                      .frames = 0,
                      .group = 10,
                      .window_frames = BENCH_REF_EVERY,
                      .size = SIM_SIZE_M,
                      .cache_dir = default_cache_dir()};
    o->desc = sim_default_desc();
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int used = 1;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 1;
        }
        if (!v && strcmp(a, "--no-ref") != 0 && strcmp(a, "--window-ref") != 0) {
            fprintf(stderr, "tryon-bench-sim: %s needs a value\n", a);
            usage(stderr);
            return -1;
        }
        if (strcmp(a, "--scene") == 0)
            o->scene = v;
        else if (strcmp(a, "--verts") == 0)
            o->verts = atoi(v);
        else if (strcmp(a, "--body-verts") == 0)
            o->body_verts = atoi(v);
        else if (strcmp(a, "--ref-body-verts") == 0)
            o->ref_body_verts = atoi(v);
        else if (strcmp(a, "--iterations") == 0)
            o->iterations = atoi(v);
        else if (strcmp(a, "--frames") == 0)
            o->frames = atoi(v);
        else if (strcmp(a, "--motion") == 0)
            o->motion = v;
        else if (strcmp(a, "--csv") == 0)
            o->csv = v;
        else if (strcmp(a, "--ref-iterations") == 0)
            o->ref_iterations = atoi(v);
        else if (strcmp(a, "--hem") == 0)
            o->hem_m = (float)atof(v);
        else if (strcmp(a, "--garment") == 0)
            o->garment = v;
        else if (strcmp(a, "--fabric") == 0)
            o->fabric = v;
        else if (strcmp(a, "--size") == 0 && strlen(v) == 1 && strchr("SMLsml", v[0]))
            o->size = v[0] == 'S' || v[0] == 's'   ? SIM_SIZE_S
                      : v[0] == 'M' || v[0] == 'm' ? SIM_SIZE_M
                                                   : SIM_SIZE_L;
        else if (strcmp(a, "--window-frames") == 0)
            o->window_frames = atoi(v);
        else if (strcmp(a, "--compare-ref") == 0)
            o->compare_ref = atoi(v);
        else if (strcmp(a, "--cache-dir") == 0)
            o->cache_dir = v;
        else if (strcmp(a, "--stretch") == 0)
            o->desc.fabric.stretch_n_m = (float)atof(v);
        else if (strcmp(a, "--follow") == 0)
            o->desc.follow = (float)atof(v);
        else if (strcmp(a, "--support") == 0)
            o->desc.support = atoi(v);
        else if (strcmp(a, "--strain-retry") == 0)
            o->desc.retry_max_strain = o->desc.retry_p99_strain = atoi(v) < 0 ? -1.0f : 0.0f;
        else if (strcmp(a, "--retry-budget") == 0)
            o->desc.retry_budget_ms = (float)atof(v);
        else if (strcmp(a, "--strain-limit") == 0)
            o->desc.strain_limit = (float)atof(v);
        else if (strcmp(a, "--friction") == 0)
            o->desc.friction = (float)atof(v);
        else if (strcmp(a, "--thickness") == 0)
            o->desc.thickness_m = (float)atof(v);
        else if (strcmp(a, "--damping") == 0)
            o->desc.damping = (float)atof(v);
        else if (strcmp(a, "--bend") == 0)
            o->desc.fabric.bend_n_m = (float)atof(v);
        else if (strcmp(a, "--backend") == 0 && (!strcmp(v, "c") || !strcmp(v, "opencl")))
            o->desc.backend = !strcmp(v, "c") ? SIM_BACKEND_C : SIM_BACKEND_OPENCL;
        else if (strcmp(a, "--solver") == 0 && (!strcmp(v, "seed") || !strcmp(v, "tryon")))
            o->desc.solver = !strcmp(v, "seed") ? SIM_SOLVER_SEED : SIM_SOLVER_TRYON;
        else if (strcmp(a, "--no-ref") == 0) {
            o->no_ref = 1;
            used = 0;
        } else if (strcmp(a, "--window-ref") == 0) {
            o->window_ref = 1;
            used = 0;
        } else {
            fprintf(stderr, "tryon-bench-sim: unknown option or bad value: %s %s\n", a, v);
            usage(stderr);
            return -1;
        }
        i += used;
    }
    int body = strcmp(o->scene, "body") == 0;
    if (pattern_fabric(o, body) < 0)
        return -1;
    if (!o->cache_dir) {
        fprintf(stderr, "tryon-bench-sim: no cache directory: set HOME, TRYON_CACHE_DIR or "
                        "--cache-dir DIR\n");
        return -1;
    }
    if ((!body && strcmp(o->scene, "drape") != 0) || o->window_frames < 1 ||
        o->window_frames > BENCH_REF_EVERY) {
        usage(stderr);
        return -1;
    }
    size_t ml = strlen(o->motion);
    int clip = body && ((ml > 4 && strcmp(o->motion + ml - 4, ".bvh") == 0) ||
                        (ml > 7 && strcmp(o->motion + ml - 7, ".lcmlog") == 0));
    if (o->frames <= 0 && !clip)     /* a clip or a log: its own length (main) */
        o->frames = body ? 495 : 90; /* body: 16.5 s, every motion of "all"; drape: 3 s */
    o->desc.iterations = o->iterations;
    if (o->ref_iterations <= 0)
        o->ref_iterations = BENCH_REF_ITERATIONS;
    return 0;
}

/* The scene's body and garment. */
static int make_scene(const bench_opts *o, sim_scene **sc, sim_garment *g)
{
    char err[160] = "";
    if (strcmp(o->scene, "drape") == 0) {
        /* 1 m x 1 m, 200 g/m^2, flat 0.3 m above the top of a 0.25 m sphere at the origin */
        float c[3] = {0, 0, 0};
        *sc = sim_scene_sphere(0.25f, c, 2000);
        if (!*sc || sim_garment_drape(o->verts, 1.0f, 0.55f, g) < 0) {
            fprintf(stderr, "tryon-bench-sim: cannot make the drape scene\n");
            return -1;
        }
        return 0;
    }
    *sc = sim_scene_body(o->motion, o->body_verts, err, sizeof err);
    if (!*sc) {
        fprintf(stderr, "tryon-bench-sim: body scene: %s\n", err);
        return -1;
    }
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    sim_reject why = {0};
    sim_scene_eval(*sc, 0.0, &xyz, &nv, &tris, &nt, &joints);
#ifdef BENCH_HAVE_PATTERN
    if (o->pattern)
        return bench_pattern_garment(o->pattern, g);
#endif
    if (sim_garment_shirt(xyz, nv, tris, nt, joints, o->verts, 0.0f, o->hem_m, g, &why) < 0) {
        fprintf(stderr, "tryon-bench-sim: shirt: %s: %s\n", sim_error_name(why.code), why.detail);
        return -1;
    }
    return 0;
}

/* A pattern garment's start (bench_pattern.h): brought from the rest pose to the scene's first
 * body (bench_pattern_turn_in), and for the measured run (measured) a buffer for
 * the limb check in *limbs_x. */
static int pattern_start(const bench_opts *o, int measured, sim *s, sim_scene *sc, bench_run *out,
                         float **limbs_x)
{
    out->arm_near_min = out->leg_near_min = out->arm_near_first = out->leg_near_first = -1.0f;
    *limbs_x = NULL;
#ifdef BENCH_HAVE_PATTERN
    if (!o->pattern)
        return 0;
    const float *xyz;
    const int32_t *tris;
    int nv, nt;
    sim_reject why = {0};
    sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, NULL);
    if (bench_pattern_turn_in(o->pattern, s, xyz, nv, tris, nt, &why) < 0) {
        fprintf(stderr, "tryon-bench-sim: settling the pattern: %s: %s\n", sim_error_name(why.code),
                why.detail);
        return -1;
    }
    if (measured && !(*limbs_x = malloc((size_t)out->nv * 3 * sizeof **limbs_x)))
        return -1;
#else
    (void)o, (void)measured, (void)s, (void)sc;
#endif
    return 0;
}

/* The limb check on frame f (bench_pattern_limbs): the first frame's, and the worst after the
 * settling frames. */
static void limbs_measure(const bench_opts *o, sim *s, const float *body_xyz, int body_nv, int f,
                          float *x, bench_run *out)
{
#ifdef BENCH_HAVE_PATTERN
    float arm, leg;
    sim_copy_positions(s, x);
    bench_pattern_limbs(o->pattern, x, body_xyz, body_nv, &arm, &leg);
    if (f == 0) {
        out->arm_near_first = arm;
        out->leg_near_first = leg;
    }
    if (f >= BENCH_SETTLE_FRAMES || f == o->frames - 1) {
        out->arm_near_min = out->arm_near_min < 0 ? arm : fminf(out->arm_near_min, arm);
        out->leg_near_min = out->leg_near_min < 0 ? leg : fminf(out->leg_near_min, leg);
    }
#else
    (void)o, (void)s, (void)body_xyz, (void)body_nv, (void)f, (void)x, (void)out;
#endif
}

/* The scene run with desc, the garment made on the body of --body-verts, the body frames from
 * one of body_verts (the references' body detail: --ref-body-verts); snapshots (positions and
 * velocities) every BENCH_REF_EVERY frames. With --window-ref the measured run (restart NULL)
 * also keeps its state --window-frames frames before each snapshot, and a windowed reference
 * (restart: the measured run) takes that state there, so each of its snapshots is where it goes
 * in those frames from where the run was. */
static int run(const bench_opts *o, const sim_desc *desc, int body_verts, const bench_run *restart,
               bench_run *out)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    memset(out, 0, sizeof *out);
    if (make_scene(o, &sc, &g) < 0) {
        sim_scene_destroy(sc);
        sim_garment_free(&g);
        return -1;
    }
    if (strcmp(o->scene, "body") == 0 && body_verts != o->body_verts) {
        /* the same garment, its attachments glued to the other body in the same pose */
        char err[160] = "";
        sim_scene *other = sim_scene_body(o->motion, body_verts, err, sizeof err);
        const float *xa, *xb;
        const int32_t *ta, *tb;
        int nva, nta, nvb, ntb;
        sim_reject why = {0};
        int e = other ? 0 : -1;
        if (other) {
            sim_scene_eval(sc, 0.0, &xa, &nva, &ta, &nta, NULL);
            sim_scene_eval(other, 0.0, &xb, &nvb, &tb, &ntb, NULL);
            e = sim_garment_rebind(&g, xa, nva, ta, nta, xb, nvb, tb, ntb, &why);
            snprintf(err, sizeof err, "%s", why.detail);
        }
        sim_scene_destroy(sc);
        sc = other;
        if (e < 0) {
            fprintf(stderr, "tryon-bench-sim: the references' body: %s\n", err);
            sim_scene_destroy(sc);
            sim_garment_free(&g);
            return -1;
        }
    }
    sim_reject why = {0};
    sim *s = sim_create(desc, &g, &why);
    sim_garment_free(&g);
    if (!s) {
        fprintf(stderr, "tryon-bench-sim: %s: %s\n", sim_error_name(why.code), why.detail);
        sim_scene_destroy(sc);
        return -1;
    }
    out->nv = sim_vertex_count(s);
    snprintf(out->device, sizeof out->device, "%s", sim_device_name(s));
    out->nsnap = o->frames / BENCH_REF_EVERY;
    out->snap = calloc((size_t)out->nsnap * out->nv * 3 + 1, sizeof *out->snap);
    out->vel = calloc((size_t)out->nsnap * out->nv * 3 + 1, sizeof *out->vel);
    out->ms = calloc((size_t)o->frames, sizeof *out->ms);
    out->st = calloc((size_t)o->frames, sizeof *out->st);
    int keep_starts = o->window_ref && !restart;
    if (keep_starts) {
        out->start_x = calloc((size_t)out->nsnap * out->nv * 3 + 1, sizeof *out->start_x);
        out->start_v = calloc((size_t)out->nsnap * out->nv * 3 + 1, sizeof *out->start_v);
    }
    int r = (out->snap && out->vel && out->ms && out->st &&
             (!keep_starts || (out->start_x && out->start_v)))
                ? 0
                : -1;
    if (restart && (restart->nv != out->nv || restart->nsnap != out->nsnap))
        r = -1;
    float *limbs_x = NULL; /* the measured run's cloth for the limb check */
    if (r == 0 && pattern_start(o, desc == &o->desc, s, sc, out, &limbs_x) < 0)
        r = -1;
    for (int f = 0; f < o->frames && r == 0; f++) {
        const float *xyz, *joints;
        const int32_t *tris;
        int nv, nt;
        sim_scene_eval(sc, (double)f * desc->frame_dt_s, &xyz, &nv, &tris, &nt, &joints);
        out->body_nv = nv;
        int e = sim_step(s, xyz, nv, tris, nt, &out->st[f], &why);
        if (e == -SIM_ERR_DIVERGED)
            out->diverged_frames++;
        else if (e < 0) {
            fprintf(stderr, "tryon-bench-sim: frame %d: %s: %s\n", f, sim_error_name(e),
                    why.detail);
            r = -1;
        }
        out->ms[f] = out->st[f].ms_total;
        if (limbs_x && (f % BENCH_LIMB_EVERY == 0 || f == o->frames - 1))
            limbs_measure(o, s, xyz, nv, f, limbs_x, out);
        if ((f + 1) % BENCH_REF_EVERY == 0 && (f + 1) / BENCH_REF_EVERY <= out->nsnap) {
            size_t at = (size_t)((f + 1) / BENCH_REF_EVERY - 1) * out->nv * 3;
            sim_copy_positions(s, out->snap + at);
            sim_copy_velocities(s, out->vel + at);
        }
        /* a window's start: window_frames before snapshot j (the first window of 10 frames
         * starts from the garment as made, which every run shares) */
        int j = (f + 1 + o->window_frames) / BENCH_REF_EVERY - 1;
        if ((keep_starts || restart) && (f + 1 + o->window_frames) % BENCH_REF_EVERY == 0 &&
            j < out->nsnap) {
            size_t at = (size_t)j * out->nv * 3;
            if (keep_starts) {
                sim_copy_positions(s, out->start_x + at);
                sim_copy_velocities(s, out->start_v + at);
            } else if (sim_set_state(s, restart->start_x + at, restart->start_v + at, &why) < 0) {
                fprintf(stderr, "tryon-bench-sim: restart at frame %d: %s\n", f, why.detail);
                r = -1;
            }
        }
    }
    free(limbs_x);
    sim_destroy(s);
    sim_scene_destroy(sc);
    return r;
}

static void run_free(bench_run *r)
{
    free(r->vel);
    free(r->start_x);
    free(r->start_v);
    free(r->ms);
    free(r->st);
    free(r->snap);
}

/* FNV-1a of the garment the scene makes (its rest positions and triangles): a reference cached
 * for another garment is not reused. */
static uint32_t garment_hash(const bench_opts *o)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    uint32_t h = 2166136261u;
    if (make_scene(o, &sc, &g) == 0) {
        const unsigned char *b = (const unsigned char *)g.xyz;
        for (size_t i = 0; i < (size_t)g.num_vertices * 3 * sizeof *g.xyz; i++)
            h = (h ^ b[i]) * 16777619u;
        b = (const unsigned char *)g.triangles;
        for (size_t i = 0; i < (size_t)g.num_triangles * 3 * sizeof *g.triangles; i++)
            h = (h ^ b[i]) * 16777619u;
    }
    sim_scene_destroy(sc);
    sim_garment_free(&g);
    return h;
}

/* The reference's model: the tryon solver on C with iters steps a frame in the world frame. */
static sim_desc ref_desc(const bench_opts *o, int iters)
{
    sim_desc d = o->desc;
    d.backend = SIM_BACKEND_C;
    d.solver = SIM_SOLVER_TRYON;
    d.iterations = iters;
    d.follow = -1.0f; /* the world frame: the physics without the moving frame's shortcut */
    d.support = 0;    /* and the same reference whether or not the run has the support pass */
    d.retry_max_strain = d.retry_p99_strain = -1.0f; /* or the strain retries */
    return d;
}

/* The body detail the references run on. */
static int ref_body(const bench_opts *o)
{
    return o->ref_body_verts > 0 && strcmp(o->scene, "body") == 0 ? o->ref_body_verts
                                                                  : o->body_verts;
}

/* The windowed reference: ref_desc(iters) restarted from the measured run's state at every
 * snapshot, so each snapshot is where the reference goes in the BENCH_REF_EVERY frames since
 * the last one from where the run was (docs/sim.md, "Error over a window"). NULL on failure. */
static float *window_reference(const bench_opts *o, int iters, const bench_run *measured)
{
    sim_desc d = ref_desc(o, iters);
    bench_run rr = {0};
    fprintf(stderr, "tryon-bench-sim: the windowed reference (%d iterations)\n", iters);
    if (run(o, &d, ref_body(o), measured, &rr) < 0) {
        run_free(&rr);
        return NULL;
    }
    float *snap = rr.snap;
    rr.snap = NULL;
    run_free(&rr);
    return snap;
}

/* The reference: the tryon solver on C with `iters` iterations (smaller steps) in the world
 * frame (whatever --follow the measured run has), its snapshots
 * cached on disk. *nv: the vertex count, or 0 to take it from the cache file. compute = 0: from
 * the cache only (NULL when it is not there). */
static float *reference(const bench_opts *o, int iters, int nsnap, int *nv, int compute)
{
    char path[512], limit[96] = ""; /* another strain limit is another model */
    if (o->desc.strain_limit != 0.0f && o->desc.strain_limit != sim_default_desc().strain_limit)
        snprintf(limit, sizeof limit, "-limit%g", o->desc.strain_limit);
    sim_desc dd = sim_default_desc(); /* another friction or damping: another model */
    if (o->desc.friction != 0.0f && o->desc.friction != dd.friction)
        snprintf(limit + strlen(limit), sizeof limit - strlen(limit), "-mu%g", o->desc.friction);
    if (o->desc.damping != 0.0f && o->desc.damping != dd.damping)
        snprintf(limit + strlen(limit), sizeof limit - strlen(limit), "-damp%g", o->desc.damping);
    if (o->desc.thickness_m != 0.0f && o->desc.thickness_m != dd.thickness_m) /* --thickness */
        snprintf(limit + strlen(limit), sizeof limit - strlen(limit), "-th%g", o->desc.thickness_m);
    if (ref_body(o) != o->body_verts) /* the same garment on a body of other detail */
        snprintf(limit + strlen(limit), sizeof limit - strlen(limit), "-body%d", ref_body(o));
    snprintf(path, sizeof path, "%s/sim-ref-v%d-%s-%s-%d-%d-%d-%g-%g-%08x%s.bin", o->cache_dir,
             BENCH_REF_VERSION, o->scene, o->motion, o->verts, iters, o->frames,
             o->desc.fabric.stretch_n_m, o->desc.fabric.bend_n_m, (unsigned)garment_hash(o), limit);
    size_t per = (size_t)nsnap * 3 * sizeof(float);
    FILE *f = fopen(path, "rb");
    if (f && nsnap > 0 && fseek(f, 0, SEEK_END) == 0) {
        long bytes = ftell(f);
        if (bytes > 0 && (size_t)bytes % per == 0 &&
            (*nv <= 0 || (size_t)bytes / per == (size_t)*nv)) {
            float *ref = malloc((size_t)bytes);
            rewind(f);
            if (ref && fread(ref, 1, (size_t)bytes, f) == (size_t)bytes) {
                fclose(f);
                *nv = (int)((size_t)bytes / per);
                return ref;
            }
            free(ref);
        }
    }
    if (f)
        fclose(f);
    if (!compute)
        return NULL;
    fprintf(stderr, "tryon-bench-sim: computing the reference (%d iterations) into %s\n", iters,
            path);
    sim_desc d = ref_desc(o, iters);
    bench_run rr = {0};
    if (run(o, &d, ref_body(o), NULL, &rr) < 0 || (*nv > 0 && rr.nv != *nv)) {
        run_free(&rr);
        return NULL;
    }
    *nv = rr.nv;
    float *ref = rr.snap;
    rr.snap = NULL;
    run_free(&rr);
    f = fopen(path, "wb");
    if (f) {
        fwrite(ref, sizeof *ref, (size_t)nsnap * *nv * 3, f);
        fclose(f);
    }
    return ref;
}

static int is_all_body(const bench_opts *o)
{
    return strcmp(o->scene, "body") == 0 && strcmp(o->motion, "all") == 0;
}

/* Which motion of "all" frame f shows (the scene's segments), -1 for any other scene. */
static int frame_segment(const bench_opts *o, int f)
{
    return is_all_body(o) ? sim_scene_all_segment((double)f * o->desc.frame_dt_s, NULL) : -1;
}

/* RMS distance (mm) between the snapshot sets a and b, over the snapshots taken after the
 * settling frames in motion segment seg (-1: all); -1 when none. */
static double rms_mm(const bench_opts *o, const float *a, const float *b, int nv, int nsnap,
                     int seg)
{
    double e2 = 0.0;
    long cnt = 0;
    for (int k = 0; a && b && k < nsnap; k++) {
        int f = (k + 1) * BENCH_REF_EVERY - 1;
        if (f < BENCH_SETTLE_FRAMES || (seg >= 0 && frame_segment(o, f) != seg))
            continue;
        for (int i = 0; i < nv * 3; i++) {
            double d = a[(size_t)k * nv * 3 + i] - b[(size_t)k * nv * 3 + i];
            e2 += d * d;
        }
        cnt += nv;
    }
    return cnt ? sqrt(e2 / (double)cnt) * 1000.0 : -1.0;
}

/* The garment's triangles as the BVH takes them, and per vertex one triangle that holds it (the
 * hint of its nearest-point search on the other mesh). */
typedef struct bench_mesh {
    int32_t (*tris)[4];
    int32_t *vertex_tri;
    int nt, nv;
} bench_mesh;

static void mesh_free(bench_mesh *m)
{
    free(m->tris);
    free(m->vertex_tri);
    memset(m, 0, sizeof *m);
}

static int mesh_of_garment(const bench_opts *o, bench_mesh *m)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    memset(m, 0, sizeof *m);
    int r = make_scene(o, &sc, &g);
    sim_scene_destroy(sc);
    if (r == 0) {
        m->nt = g.num_triangles;
        m->nv = g.num_vertices;
        m->tris = calloc((size_t)m->nt + 1, sizeof *m->tris);
        m->vertex_tri = calloc((size_t)m->nv + 1, sizeof *m->vertex_tri);
        r = m->tris && m->vertex_tri ? 0 : -1;
        for (int t = 0; r == 0 && t < m->nt; t++)
            for (int k = 0; k < 3; k++) {
                m->tris[t][k] = g.triangles[t * 3 + k];
                m->vertex_tri[m->tris[t][k]] = t;
            }
    }
    sim_garment_free(&g);
    if (r < 0)
        mesh_free(m);
    return r;
}

/* Sum of squared distances (m^2) of the points pa to the surface of the garment at pb. bvh: a
   tree over the garment's triangles (any positions: it is refitted to pb here). */
static double surface_d2(const bench_mesh *m, sim_bvh *bvh, const float (*pa)[4],
                         const float (*pb)[4])
{
    sim_bvh_refit(bvh, pb, pb, (const int32_t(*)[4])m->tris, 0.0f);
    double e2 = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : e2)
    for (int i = 0; i < m->nv; i++) {
        float q[3], bary[3], dist = 0.0f;
        if (sim_bvh_nearest_from(bvh, pb, (const int32_t(*)[4])m->tris, pa[i], INFINITY,
                                 m->vertex_tri[i], q, bary, &dist) >= 0)
            e2 += (double)dist * dist;
    }
    return e2;
}

/* Per snapshot of the snapshot sets a and b: the sum of squared distances (m^2) of each
 * garment's vertices to the other's surface, both ways (the shape's difference without the
 * cloth's sliding along itself; docs/sim.md, "Body detail and the shape error"). NULL when
 * either set or the mesh is missing. Computed once per pair; shape_rms_mm takes the RMS over
 * any motion. */
static double *shape_d2(const bench_mesh *m, const float *a, const float *b, int nsnap)
{
    sim_bvh bvh;
    if (!a || !b || m->nt <= 0 || nsnap <= 0 || sim_bvh_init(&bvh, m->nt) != 0)
        return NULL;
    float(*pa)[4] = calloc((size_t)m->nv + 1, sizeof *pa);
    float(*pb)[4] = calloc((size_t)m->nv + 1, sizeof *pb);
    double *d2 = pa && pb ? calloc((size_t)nsnap, sizeof *d2) : NULL;
    for (int k = 0; d2 && k < nsnap; k++) {
        size_t at = (size_t)k * m->nv * 3;
        for (int i = 0; i < m->nv; i++)
            for (int d = 0; d < 4; d++) {
                pa[i][d] = d < 3 ? a[at + (size_t)i * 3 + d] : 0.0f;
                pb[i][d] = d < 3 ? b[at + (size_t)i * 3 + d] : 0.0f;
            }
        if (k == 0) /* the garment's topology: built once, refitted to every snapshot */
            sim_bvh_build(&bvh, (const float(*)[4])pb, (const float(*)[4])pb,
                          (const int32_t(*)[4])m->tris, m->nt, 0.0f);
        d2[k] = surface_d2(m, &bvh, (const float(*)[4])pa, (const float(*)[4])pb) +
                surface_d2(m, &bvh, (const float(*)[4])pb, (const float(*)[4])pa);
    }
    sim_bvh_free(&bvh);
    free(pa);
    free(pb);
    return d2;
}

/* As rms_mm, from shape_d2's sums: over the snapshots after the settling frames in motion
 * segment seg (-1: all); -1 when none. */
static double shape_rms_mm(const bench_opts *o, const double *d2, int nv, int nsnap, int seg)
{
    double e2 = 0.0;
    long cnt = 0;
    for (int k = 0; d2 && k < nsnap; k++) {
        int f = (k + 1) * BENCH_REF_EVERY - 1;
        if (f < BENCH_SETTLE_FRAMES || (seg >= 0 && frame_segment(o, f) != seg))
            continue;
        e2 += d2[k];
        cnt += 2L * nv;
    }
    return cnt ? sqrt(e2 / (double)cnt) * 1000.0 : -1.0;
}

/* --compare-ref M: the distance between the references of --ref-iterations and of M. */
static int compare_refs(const bench_opts *o)
{
    int nsnap = o->frames / BENCH_REF_EVERY, nv = 0;
    float *a = reference(o, o->ref_iterations, nsnap, &nv, 1);
    float *b = a ? reference(o, o->compare_ref, nsnap, &nv, 1) : NULL;
    if (!b) {
        free(a);
        return 1;
    }
    printf("{\"scene\":\"%s\",\"motion\":\"%s\",\"verts\":%d,\"ref_iterations\":%d,"
           "\"compare_ref\":%d,\"rms_mm\":%.2f",
           o->scene, o->motion, nv, o->ref_iterations, o->compare_ref,
           rms_mm(o, a, b, nv, nsnap, -1));
    for (int m = 0; is_all_body(o) && m < sim_scene_segment_count(); m++)
        printf(",\"%s_mm\":%.2f", sim_scene_segment_name(m), rms_mm(o, a, b, nv, nsnap, m));
    printf("}\n");
    free(a);
    free(b);
    return 0;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static float percentile(const float *v, int n, float p)
{
    float *s = malloc((size_t)(n > 0 ? n : 1) * sizeof *s);
    if (!s || n == 0) {
        free(s);
        return 0.0f;
    }
    memcpy(s, v, (size_t)n * sizeof *s);
    qsort(s, (size_t)n, sizeof *s, cmp_float);
    float r = s[(int)floorf(p * (float)(n - 1) + 0.5f)];
    free(s);
    return r;
}

static void print_groups(const bench_opts *o, const bench_run *r)
{
    printf("%-9s %8s %8s %8s %8s %8s %6s %8s %6s %s\n", "frames", "ms_med", "ms_max", "bvh+fp",
           "iter_ms", "strain%", "p99%", "pen", "pen_mm", "state");
    for (int f0 = 0; f0 < o->frames; f0 += o->group) {
        int n = f0 + o->group <= o->frames ? o->group : o->frames - f0;
        float ms_max = 0, strain = 0, p99 = 0, pen_mm = 0, pre = 0, it = 0;
        int pen = 0, worst = 0;
        for (int f = f0; f < f0 + n; f++) {
            const sim_frame_stats *s = &r->st[f];
            ms_max = fmaxf(ms_max, r->ms[f]);
            strain = fmaxf(strain, s->max_strain);
            p99 = fmaxf(p99, s->p99_strain);
            pen = s->penetrating > pen ? s->penetrating : pen;
            pen_mm = fmaxf(pen_mm, s->max_pen_mm);
            pre += (s->ms_bvh + s->ms_feature_points) / (float)n;
            it += s->ms_iterations / (float)n;
            worst = (int)s->state > worst ? (int)s->state : worst;
        }
        printf("%4d-%-4d %8.2f %8.2f %8.2f %8.2f %8.2f %6.2f %8d %6.1f %s\n", f0, f0 + n - 1,
               percentile(r->ms + f0, n, 0.5f), ms_max, pre, it, strain * 100.0f, p99 * 100.0f, pen,
               pen_mm, sim_state_name((sim_state)worst));
    }
}

static void write_csv(const char *path, const bench_run *r, int frames)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "tryon-bench-sim: cannot write %s\n", path);
        return;
    }
    fprintf(f, "frame,ms,bvh,fp,contacts,iterations,metrics,max_strain,p99_strain,penetrating,"
               "max_pen_mm,state,settle_rounds\n");
    for (int i = 0; i < frames; i++) {
        const sim_frame_stats *s = &r->st[i];
        fprintf(f, "%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.5f,%.5f,%d,%.2f,%d,%d\n", i, r->ms[i],
                s->ms_bvh, s->ms_feature_points, s->ms_contacts, s->ms_iterations, s->ms_metrics,
                s->max_strain, s->p99_strain, s->penetrating, s->max_pen_mm, (int)s->state,
                s->settle_rounds);
    }
    fclose(f);
}

/* --motion FILE.bvh or FILE.lcmlog without --frames: the whole clip or session (the scene's
 * duration; a clip on a small body). */
static int clip_frames(bench_opts *o)
{
    char err[256] = "";
    sim_scene *sc = sim_scene_body(o->motion, 2000, err, sizeof err);
    if (!sc) {
        fprintf(stderr, "tryon-bench-sim: body scene: %s\n", err);
        return -1;
    }
    o->frames = (int)floor(sim_scene_duration(sc) / o->desc.frame_dt_s + 0.5);
    sim_scene_destroy(sc);
    return 0;
}

/* The figures of docs/sim-real-motion.md's "Real motion" over the published frames: the share of
 * frames with no vertex over 1 mm inside the body, and with max strain <= 3 % and p99 <= 1 % (after
 * the settling frames); the frames carried by the body (no attempt solved them) and the longest
 * run of them. */
typedef struct frame_shares {
    double pen_free_pct, strain_ok_pct;
    int carried, carried_run;
} frame_shares;

static frame_shares shares(const bench_run *r, int frames, int settle)
{
    frame_shares f = {0};
    int pen_free = 0, strain_ok = 0, run = 0;
    for (int i = 0; i < frames; i++) {
        const sim_frame_stats *s = &r->st[i];
        pen_free += s->penetrating == 0;
        strain_ok += i >= settle && s->max_strain <= 0.03f && s->p99_strain <= 0.01f;
        run = s->state == SIM_STATE_CARRIED ? run + 1 : 0;
        f.carried += s->state == SIM_STATE_CARRIED;
        f.carried_run = run > f.carried_run ? run : f.carried_run;
    }
    f.pen_free_pct = frames > 0 ? 100.0 * pen_free / frames : 0.0;
    f.strain_ok_pct = frames > settle ? 100.0 * strain_ok / (frames - settle) : 0.0;
    return f;
}

/* --garment: the pattern dressed once on the scene's body (bench_pattern.h). */
static int make_pattern(bench_opts *o)
{
#ifdef BENCH_HAVE_PATTERN
    char err[300] = "";
    sim_scene *sc = sim_scene_body(o->motion, o->body_verts, err, sizeof err);
    bench_pattern_desc d = {.path = o->garment,
                            .size = (sim_size)o->size,
                            .fabric = o->fabric,
                            .target_vertices = o->verts,
                            .body_verts = o->body_verts};
    o->pattern = sc ? bench_pattern_create(&d, sc, err, sizeof err) : NULL;
    sim_scene_destroy(sc);
    if (!o->pattern) {
        fprintf(stderr, "tryon-bench-sim: --garment %s: %s\n", o->garment, err);
        return -1;
    }
    bench_pattern_info in;
    bench_pattern_get_info(o->pattern, &in);
    printf("pattern %s %s %s: %d vertices (%.1f mm mesh; %d in sleeves, %d in legs), dressed in "
           "%.0f ms (%.0f in all), seams %.2f mm, %d inside, strain max %.1f %% p99 %.2f %%\n",
           o->garment, sim_size_name((sim_size)o->size), o->fabric ? o->fabric : "cotton",
           in.vertices, in.spacing_m * 1e3f, in.arm_vertices, in.leg_vertices, in.dress_ms,
           in.total_ms, in.seam_gap_mm, in.penetrating, in.max_strain * 100.0f,
           in.p99_strain * 100.0f);
    return 0;
#else
    (void)o;
    return -1;
#endif
}

static void free_pattern(bench_opts *o)
{
#ifdef BENCH_HAVE_PATTERN
    bench_pattern_destroy(o->pattern);
    o->pattern = NULL;
#else
    (void)o;
#endif
}

/* The JSON line's pattern fields (none without --garment). */
static void print_pattern_json(const bench_opts *o, const bench_run *r)
{
#ifdef BENCH_HAVE_PATTERN
    if (!o->pattern)
        return;
    bench_pattern_info in;
    bench_pattern_get_info(o->pattern, &in);
    printf(",\"garment\":\"%s\",\"size\":\"%s\",\"fabric\":\"%s\",\"spacing_mm\":%.2f,"
           "\"dress_ms\":%.1f,\"dress_seam_gap_mm\":%.2f,\"dress_penetrating\":%d,"
           "\"dress_max_strain\":%.4f,\"dress_p99_strain\":%.4f,\"limb_near_cm\":%.1f,"
           "\"sleeve_verts\":%d,\"leg_verts\":%d,\"sleeve_near_first\":%.3f,"
           "\"sleeve_near_min\":%.3f,\"leg_near_first\":%.3f,\"leg_near_min\":%.3f",
           o->garment, sim_size_name((sim_size)o->size), o->fabric ? o->fabric : "cotton",
           in.spacing_m * 1e3f, in.dress_ms, in.seam_gap_mm, in.penetrating, in.max_strain,
           in.p99_strain, BENCH_LIMB_NEAR_M * 100.0f, in.arm_vertices, in.leg_vertices,
           r->arm_near_first, r->arm_near_min, r->leg_near_first, r->leg_near_min);
#else
    (void)o, (void)r;
#endif
}

int main(int argc, char **argv)
{
    bench_opts o;
    int pr = parse(argc, argv, &o);
    if (pr != 0)
        return pr > 0 ? 0 : 2;
    if (o.cache_dir && make_dirs(o.cache_dir) != 0) {
        fprintf(stderr, "tryon-bench-sim: cannot create the cache directory %s\n", o.cache_dir);
        return 1;
    }
    if (o.frames <= 0 && clip_frames(&o) < 0)
        return 1;
    if (o.garment && make_pattern(&o) < 0)
        return 1;
    if (o.compare_ref > 0) {
        int e = compare_refs(&o);
        free_pattern(&o);
        return e;
    }
    bench_run r;
    /* the share of the machine's time its hypervisor took while the run was timed: a virtual
       machine's slow phases show here (docs/sim.md, "Measured") */
    unsigned long long tot0 = 0, st0 = 0, tot1 = 0, st1 = 0;
    int ticks = cpu_ticks(&tot0, &st0);
    if (run(&o, &o.desc, o.body_verts, NULL, &r) < 0) {
        free_pattern(&o);
        return 1;
    }
    ticks |= cpu_ticks(&tot1, &st1);
    double steal_pct =
        ticks == 0 && tot1 > tot0 ? 100.0 * (double)(st1 - st0) / (double)(tot1 - tot0) : -1.0;
    print_groups(&o, &r);
    if (o.csv)
        write_csv(o.csv, &r, o.frames);

    int warm = o.frames > 10 ? 5 : 0; /* the first frames fault pages in */
    float ms_med = percentile(r.ms + warm, o.frames - warm, 0.5f);
    float ms_p95 = percentile(r.ms + warm, o.frames - warm, 0.95f);
    /* the same without the penetration and strain metrics, which only measure */
    for (int f = 0; f < o.frames; f++)
        r.ms[f] -= r.st[f].ms_metrics;
    float ms_nm = percentile(r.ms + warm, o.frames - warm, 0.5f);
    float max_strain = 0, p99 = 0, pen_mm = 0;
    int pen = 0, recovered = 0, strain_retried = 0, settled = 0,
        settle = o.frames > BENCH_SETTLE_FRAMES ? BENCH_SETTLE_FRAMES : 0;
    for (int f = 0; f < o.frames; f++) {
        const sim_frame_stats *s = &r.st[f];
        if (f >= settle) {
            max_strain = fmaxf(max_strain, s->max_strain);
            p99 = fmaxf(p99, s->p99_strain);
        }
        pen = s->penetrating > pen ? s->penetrating : pen;
        pen_mm = fmaxf(pen_mm, s->max_pen_mm);
        recovered += s->state == SIM_STATE_RECOVERED;
        strain_retried += s->strain_retries > 0;
        settled += s->settle_rounds > 0;
    }
    frame_shares fs = shares(&r, o.frames, settle);
    int nv_ref = r.nv;
    /* the references' body detail, as run (the run's own unless --ref-body-verts) */
    int ref_body_nv = r.body_nv;
    if (!o.no_ref && ref_body(&o) != o.body_verts) {
        char err[160] = "";
        sim_scene *rb = sim_scene_body(o.motion, ref_body(&o), err, sizeof err);
        const float *xyz;
        const int32_t *tris;
        int nt;
        if (rb)
            sim_scene_eval(rb, 0.0, &xyz, &ref_body_nv, &tris, &nt, NULL);
        sim_scene_destroy(rb);
    }
    float *ref = o.no_ref ? NULL : reference(&o, o.ref_iterations, r.nsnap, &nv_ref, 1);
    double cloth_error_mm = ref ? rms_mm(&o, r.snap, ref, r.nv, r.nsnap, -1) : -1.0;
    /* the reference's own uncertainty: its distance to the reference of half the iterations,
     * when that one is in the cache (docs/sim.md: the reference does not converge everywhere)
     */
    float *half = ref ? reference(&o, o.ref_iterations / 2, r.nsnap, &nv_ref, 0) : NULL;
    double ref_unc_mm = half ? rms_mm(&o, ref, half, r.nv, r.nsnap, -1) : -1.0;
    free(half);
    /* --window-ref: the same over windows of BENCH_REF_EVERY frames from the run's own state,
     * and that reference's uncertainty likewise (half its iterations, from the same states) */
    float *win = !o.no_ref && o.window_ref ? window_reference(&o, o.ref_iterations, &r) : NULL;
    float *win_half = win ? window_reference(&o, o.ref_iterations / 2, &r) : NULL;
    double win_mm = win ? rms_mm(&o, r.snap, win, r.nv, r.nsnap, -1) : -1.0;
    double win_unc_mm = win_half ? rms_mm(&o, win, win_half, r.nv, r.nsnap, -1) : -1.0;
    /* the shape's error: the same references, each garment's vertices to the other's surface */
    bench_mesh mesh = {0};
    if (ref && (mesh_of_garment(&o, &mesh) < 0 || mesh.nv != r.nv))
        mesh_free(&mesh);
    double *sh = shape_d2(&mesh, r.snap, ref, r.nsnap);
    double *sh_win = shape_d2(&mesh, r.snap, win, r.nsnap);
    double *sh_unc = shape_d2(&mesh, win, win_half, r.nsnap);
    double shape_mm = shape_rms_mm(&o, sh, r.nv, r.nsnap, -1);
    double win_shape_mm = shape_rms_mm(&o, sh_win, r.nv, r.nsnap, -1);
    double win_shape_unc_mm = shape_rms_mm(&o, sh_unc, r.nv, r.nsnap, -1);
    if (is_all_body(&o)) {
        /* per motion: strain after the settling frames, error against the reference */
        printf("%-10s %9s %8s %9s %9s %9s %9s %9s %9s\n", "motion", "strain%", "p99%", "error_mm",
               "window_mm", "win_unc", "shape_mm", "win_shape", "shape_unc");
        for (int m = 0; m < sim_scene_segment_count(); m++) {
            float mx = 0, p = 0;
            int seen = 0;
            for (int f = settle; f < o.frames; f++)
                if (frame_segment(&o, f) == m) {
                    mx = fmaxf(mx, r.st[f].max_strain);
                    p = fmaxf(p, r.st[f].p99_strain);
                    seen++;
                }
            if (!seen)
                continue; /* --frames stopped before this motion */
            printf("%-10s %9.2f %8.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f\n",
                   sim_scene_segment_name(m), mx * 100.0f, p * 100.0f,
                   ref ? rms_mm(&o, r.snap, ref, r.nv, r.nsnap, m) : -1.0,
                   win ? rms_mm(&o, r.snap, win, r.nv, r.nsnap, m) : -1.0,
                   win_half ? rms_mm(&o, win, win_half, r.nv, r.nsnap, m) : -1.0,
                   shape_rms_mm(&o, sh, r.nv, r.nsnap, m),
                   shape_rms_mm(&o, sh_win, r.nv, r.nsnap, m),
                   shape_rms_mm(&o, sh_unc, r.nv, r.nsnap, m));
        }
    }
    free(ref);
    free(win);
    free(win_half);
    mesh_free(&mesh);
    free(sh);
    free(sh_win);
    free(sh_unc);
    /* the moving frame in effect (sim.h: 0 = 1, < 0 = none; the seed and garments with fewer
       than 3 attachments, such as the drape, have none) */
    float follow = o.desc.follow == 0.0f ? 1.0f : fmaxf(o.desc.follow, 0.0f);
    if (o.desc.solver == SIM_SOLVER_SEED || strcmp(o.scene, "body") != 0)
        follow = 0.0f;
    /* the support hierarchy in effect: the tryon solver on a garment without attachments */
    int support =
        o.desc.support >= 0 && o.desc.solver == SIM_SOLVER_TRYON && strcmp(o.scene, "body") != 0;
    int strain_retry = o.desc.solver == SIM_SOLVER_TRYON && o.desc.retry_max_strain >= 0.0f;
    printf("{\"scene\":\"%s\",\"motion\":\"%s\",\"solver\":\"%s\",\"backend\":\"%s\","
           "\"device\":\"%s\",\"verts\":%d,\"iterations\":%d,\"frames\":%d,"
           "\"ms_median\":%.3f,\"ms_p95\":%.3f,\"max_strain\":%.5f,\"p99_strain\":%.5f,"
           "\"penetrating\":%d,\"max_pen_mm\":%.2f,\"cloth_error_mm\":%.2f,"
           "\"recovered_frames\":%d,\"diverged_frames\":%d,\"stretch_n_m\":%g,"
           "\"ref_iterations\":%d,\"ref_uncertainty_mm\":%.2f,\"ms_median_no_metrics\":%.3f,"
           "\"follow\":%g,\"settle_frames\":%d,\"support\":%d,\"strain_retry\":%d,"
           "\"strain_retried_frames\":%d,\"cloth_error_window_mm\":%.2f,"
           "\"window_uncertainty_mm\":%.2f,\"cloth_shape_error_mm\":%.2f,"
           "\"shape_window_mm\":%.2f,\"shape_window_uncertainty_mm\":%.2f,\"body_verts\":%d,"
           "\"ref_body_verts\":%d,\"window_frames\":%d,\"cpu_steal_pct\":%.1f,"
           "\"pen_free_frames_pct\":%.2f,\"strain_ok_frames_pct\":%.2f,\"carried_frames\":%d,"
           "\"carried_run\":%d",
           o.scene, strcmp(o.scene, "body") == 0 ? o.motion : "none",
           o.desc.solver == SIM_SOLVER_SEED ? "seed" : "tryon",
           o.desc.backend == SIM_BACKEND_C ? "c" : "opencl", r.device, r.nv, o.iterations, o.frames,
           ms_med, ms_p95, max_strain, p99, pen, pen_mm, cloth_error_mm, recovered,
           r.diverged_frames, o.desc.fabric.stretch_n_m, o.ref_iterations, ref_unc_mm, ms_nm,
           follow, settled, support, strain_retry, strain_retried, win_mm, win_unc_mm, shape_mm,
           win_shape_mm, win_shape_unc_mm, r.body_nv, ref_body_nv,
           o.window_ref ? o.window_frames : -1, steal_pct, fs.pen_free_pct, fs.strain_ok_pct,
           fs.carried, fs.carried_run);
    print_pattern_json(&o, &r);
    printf("}\n");
    run_free(&r);
    free_pattern(&o);
    return 0;
}
