/* Which size fits (docs/garments.md, "Which size fits"): a pattern dressed in each size on the
 * body, the fit measured per region, and the smallest size that is not tight anywhere picked. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "garments.h"

/* A region with fewer garment vertices over it says little (a sleeve cap's edge over the chest). */
#define GAR_PICK_MIN_VERTICES 20

/* The tightest region of a dressed size: the largest 95th-percentile strain over the regions. */
static float tightness(const gar_fit *f, int *where)
{
    float t = 0;
    *where = -1;
    for (int r = 0; r < GAR_REGION_COUNT; r++)
        if (f->region[r].vertices >= GAR_PICK_MIN_VERTICES && f->region[r].p95_strain > t)
            t = f->region[r].p95_strain, *where = r;
    return t;
}

/* Loose: the median distance to the body, over the regions the garment covers. */
static float looseness_mm(const gar_fit *f)
{
    float sum = 0;
    int n = 0;
    for (int r = 0; r < GAR_REGION_COUNT; r++)
        if (f->region[r].vertices >= GAR_PICK_MIN_VERTICES)
            sum += f->region[r].gap_mm, n++;
    return n ? sum / (float)n : 0;
}

static int dress_size(const char *path, const struct fit_model *body, gar_size size,
                      const gar_mesh_desc *md, const gar_dress_desc *dd, gar_size_pick *out,
                      gar_reject *why)
{
    gar_pattern p;
    gar_mesh m = {0};
    int rc = gar_pattern_load(path, &p, why);
    if (rc)
        return rc;
    gar_pattern_grade(&p, size);
    rc = gar_mesh_build(&p, md, &m, why);
    if (!rc)
        rc = gar_mesh_place(&p, &m, body, NULL, NULL, NULL, why);
    if (!rc)
        rc = gar_dress_tryon(&p, &m, body, dd, &out->stats[size], why);
    if (!rc && (rc = gar_fit_measure(&m, body, &out->fit[size])))
        snprintf(why->detail, sizeof why->detail, "measuring the fit of size %c", "SML"[size]);
    if (!rc) {
        out->dressed[size] = 1;
        out->tight[size] = tightness(&out->fit[size], &out->tight_region[size]);
        out->loose_mm[size] = looseness_mm(&out->fit[size]);
    }
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    return rc;
}

int gar_pick_size(const char *path, const struct fit_model *body, const gar_mesh_desc *md,
                  const gar_dress_desc *dd, gar_size_pick *out, gar_reject *why)
{
    gar_reject scratch;
    why = why ? why : &scratch;
    if (!path || !body || !out)
        return -GAR_ERR_ARG;
    memset(out, 0, sizeof *out);
    const gar_fabric *fab = dd && dd->fabric ? dd->fabric : gar_fabric_find("cotton");
    out->limit = GAR_PICK_TIGHT_FACTOR * fab->max_strain;
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s++) {
        int rc = dress_size(path, body, (gar_size)s, md, dd, out, why);
        if (rc)
            return rc;
    }
    /* the smallest size not tight anywhere; none: the least tight (the body needs a larger one) */
    int pick = -1;
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L && pick < 0; s++)
        if (out->tight[s] <= out->limit)
            pick = s;
    int fits = pick >= 0;
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L && !fits; s++)
        if (pick < 0 || out->tight[s] < out->tight[pick])
            pick = s;
    const char *names = "SML", *where = gar_region_name((gar_region)out->tight_region[pick]);
    float limit_pc = 100 * out->limit, tight_pc = 100 * out->tight[pick];
    if (fits)
        snprintf(out->reason, sizeof out->reason,
                 "%c: the smallest size whose every region stretches at most %.1f %% (p95; "
                 "tightest %s %.1f %%, median gap %.0f mm)",
                 names[pick], limit_pc, where, tight_pc, out->loose_mm[pick]);
    else
        snprintf(
            out->reason, sizeof out->reason,
            "%c: every size stretches more than %.1f %% somewhere, %c the least (%s %.1f %%)%s",
            names[pick], limit_pc, names[pick], where, tight_pc,
            pick == GAR_SIZE_L ? ": the body may need a size above L" : "");
    out->size = (gar_size)pick;
    return 0;
}
