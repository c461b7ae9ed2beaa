/* Sizes graded from one base (size M) and the fabric presets: each number in one place. */
#include <ctype.h>
#include <math.h>
#include <string.h>

#include "garments.h"

/* Grading steps between neighbouring sizes: about one 4 cm chest step on a 100 cm girth and a
 * 3 cm length step on a 100 cm garment, the usual ready-to-wear grade. */
#define GAR_GRADE_GIRTH  0.04f
#define GAR_GRADE_LENGTH 0.03f

int gar_size_from_name(const char *name)
{
    static const char names[] = "SML";
    if (!name || !name[0] || name[1])
        return -1;
    const char *at = strchr(names, toupper((unsigned char)name[0]));
    return at ? (int)(at - names) : -1;
}

/* The highest point of the pattern as the file places it (m): a top hangs from it (shoulders),
 * a skirt or trousers from their waist. */
static float pattern_top(const gar_pattern *p)
{
    float top = -INFINITY;
    for (int i = 0; i < p->num_panels; i++)
        for (int v = 0; v < p->panels[i].num_vertices; v++) {
            float w[3];
            gar_panel_to_world(&p->panels[i], p->panels[i].uv_m + 2 * v, w);
            top = fmaxf(top, w[1]);
        }
    return top;
}

void gar_pattern_grade(gar_pattern *p, gar_size size)
{
    float step = (float)size - (float)GAR_SIZE_M;
    float gx = 1 + step * GAR_GRADE_GIRTH, gy = 1 + step * GAR_GRADE_LENGTH;
    /* Lengths grow down from the garment's top, which stays where the file puts it (the body's
     * waist for a skirt: scaled about the floor, size S's waistband sat 3 cm lower and L's 3 cm
     * higher). Exact for panels whose v axis stays vertical (rotations about y). */
    float top = p && p->num_panels ? pattern_top(p) : 0;
    for (int i = 0; p && i < p->num_panels; i++) {
        gar_panel *pn = &p->panels[i];
        for (int v = 0; v < pn->num_vertices; v++) {
            pn->uv_m[2 * v] *= gx;
            pn->uv_m[2 * v + 1] *= gy;
        }
        for (int e = 0; e < pn->num_edges; e++) {
            gar_edge *ed = &pn->edges[e];
            for (int k = 0; k < 2; k++) {
                ed->ctrl[k][0] *= gx;
                ed->ctrl[k][1] *= gy;
            }
            ed->radius_m *= gx > gy ? gx : gy;
        }
        pn->translation_m[0] *= gx;
        pn->translation_m[1] = top + (pn->translation_m[1] - top) * gy;
        pn->translation_m[2] *= gx;
    }
}

/* Membrane stiffnesses as sim_fabric (N/m), densities from fabric weights (g/m^2): shirting
 * cotton ~150, denim ~400 (12 oz), cotton jersey ~180, silk charmeuse ~80. Stretch and shear
 * ratios follow the fabrics' feel: denim stiff and firm, jersey soft and stretchy in shear,
 * silk light and limp in bending. max_strain: the elongation the seed's velocity correction
 * tolerates (seed 003, Vassilev), jersey knits stretch more than wovens. */
static const gar_fabric fabrics[] = {
    {"cotton", 0.15f, 1000.0f, 100.0f, 2.0f, 0.4f, 0.03f, 2e-5f},
    {"denim", 0.40f, 3000.0f, 300.0f, 10.0f, 0.5f, 0.02f, 3e-4f},
    {"jersey", 0.18f, 300.0f, 30.0f, 1.0f, 0.45f, 0.08f, 8e-6f},
    {"silk", 0.08f, 600.0f, 40.0f, 0.3f, 0.25f, 0.03f, 2e-6f},
};

int gar_fabric_count(void)
{
    return (int)(sizeof fabrics / sizeof fabrics[0]);
}

const gar_fabric *gar_fabric_get(int i)
{
    return i >= 0 && i < gar_fabric_count() ? &fabrics[i] : NULL;
}

const gar_fabric *gar_fabric_find(const char *name)
{
    for (int i = 0; name && i < gar_fabric_count(); i++)
        if (!strcmp(fabrics[i].name, name))
            return &fabrics[i];
    return NULL;
}
