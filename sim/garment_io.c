/* Garments as Wavefront OBJ: 'v x y z' and 'f a b c' (1-based, 'a/b/c' forms accepted), and a
 * "# grid W H" comment for grid garments. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"

int sim_garment_save_obj(const sim_garment *g, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -SIM_ERR_FILE;
    fprintf(f, "# tryon garment %s\n", g->id);
    if (g->grid_w > 0)
        fprintf(f, "# grid %d %d\n", g->grid_w, g->grid_h);
    for (int i = 0; i < g->num_vertices; i++)
        fprintf(f, "v %.9g %.9g %.9g\n", g->xyz[i * 3], g->xyz[i * 3 + 1], g->xyz[i * 3 + 2]);
    for (int t = 0; t < g->num_triangles; t++)
        fprintf(f, "f %d %d %d\n", g->triangles[t * 3] + 1, g->triangles[t * 3 + 1] + 1,
                g->triangles[t * 3 + 2] + 1);
    return fclose(f) == 0 ? 0 : -SIM_ERR_FILE;
}

static int grow(void **p, int *cap, int need, size_t elem)
{
    if (need <= *cap)
        return 0;
    int c = *cap ? *cap * 2 : 4096;
    while (c < need)
        c *= 2;
    void *q = realloc(*p, (size_t)c * elem);
    if (!q)
        return -1;
    *p = q;
    *cap = c;
    return 0;
}

/* Reads a whole-number field in lo..hi; anything else (overflow included) is refused. */
static int read_int(const char **c, long lo, long hi, long *out)
{
    char *e;
    long x = strtol(*c, &e, 10);
    if (e == *c || x < lo || x > hi)
        return -1;
    *out = x;
    *c = e;
    return 0;
}

/* Parses one line into g. Returns 0, -1 (bad line: *what says why) or -2 (out of memory). */
static int parse_line(sim_garment *g, const char *line, int *vcap, int *tcap, const char **what)
{
    if (strncmp(line, "# grid ", 7) == 0) {
        const char *c = line + 7;
        long w, h;
        *what = "grid: two sizes in 2..GARMENT_MAX_VERTICES expected";
        if (read_int(&c, 2, GARMENT_MAX_VERTICES, &w) || read_int(&c, 2, GARMENT_MAX_VERTICES, &h))
            return -1;
        g->grid_w = (int)w;
        g->grid_h = (int)h;
    } else if (line[0] == 'v' && line[1] == ' ') {
        float p[3];
        *what = "vertex: three numbers expected, at most GARMENT_MAX_VERTICES vertices";
        if (sscanf(line + 2, "%f %f %f", &p[0], &p[1], &p[2]) != 3 ||
            g->num_vertices >= GARMENT_MAX_VERTICES)
            return -1;
        if (grow((void **)&g->xyz, vcap, (g->num_vertices + 1) * 3, sizeof(float)) < 0)
            return -2;
        memcpy(&g->xyz[g->num_vertices * 3], p, sizeof p);
        g->num_vertices++;
    } else if (line[0] == 'f' && line[1] == ' ') {
        int v[3];
        const char *c = line + 2;
        /* Indices are 1-based and bounded before the int conversion; relative (negative) OBJ
         * indices are not used by tryon garments. */
        *what = "face: three indices in 1..GARMENT_MAX_VERTICES expected";
        if (g->num_triangles >= 2 * GARMENT_MAX_VERTICES)
            return -1;
        for (int n = 0; n < 3; n++) {
            long x;
            if (read_int(&c, 1, GARMENT_MAX_VERTICES, &x))
                return -1;
            v[n] = (int)x - 1;
            while (*c && *c != ' ' && *c != '\t')
                c++; /* skip /vt/vn */
        }
        if (grow((void **)&g->triangles, tcap, (g->num_triangles + 1) * 3, sizeof(int32_t)) < 0)
            return -2;
        memcpy(&g->triangles[g->num_triangles * 3], v, sizeof v);
        g->num_triangles++;
    }
    return 0;
}

int sim_garment_load_obj(const char *path, sim_garment *out, sim_reject *why)
{
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "r");
    if (!f)
        return sim_reject_set(why, SIM_ERR_FILE, "%s: cannot open", path);
    const char *base = strrchr(path, '/');
    snprintf(out->id, sizeof out->id, "%s", base ? base + 1 : path);
    char line[512];
    int vcap = 0, tcap = 0, lineno = 0, r = 0;
    const char *what = "";
    while (r == 0 && fgets(line, sizeof line, f)) {
        lineno++;
        r = parse_line(out, line, &vcap, &tcap, &what);
    }
    fclose(f);
    if (r < 0) {
        sim_garment_free(out);
        return sim_reject_set(why, r == -2 ? SIM_ERR_NO_MEMORY : SIM_ERR_FILE, "%s:%d: %s", path,
                              lineno, r == -2 ? "out of memory" : what);
    }
    r = sim_garment_validate(out, 0, why);
    if (r < 0) {
        char detail[100];
        snprintf(detail, sizeof detail, "%.99s", why ? why->detail : "");
        sim_garment_free(out);
        if (why)
            snprintf(why->detail, sizeof why->detail, "%.50s: %.99s", path, detail);
    }
    return r;
}
