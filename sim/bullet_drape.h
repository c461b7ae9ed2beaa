/* Bullet's soft-body cloth on the drape scene, behind a C interface (Bullet is C++ and has no C
 * interface for soft bodies): the comparison the issue names, measured here rather than quoted.
 * Only tryon-bench-bullet uses it. */
#ifndef TRYON_BULLET_DRAPE_H
#define TRYON_BULLET_DRAPE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bullet_drape bullet_drape;

typedef struct bullet_drape_desc {
    int side;         /* vertices per side of the square sheet */
    float side_m;     /* sheet side */
    float height_m;   /* sheet height (flat, centred on x = z = 0) */
    float sphere_r_m; /* fixed sphere at the origin */
    float mass_kg;    /* whole sheet */
    int iterations;   /* btSoftBody::m_cfg.piterations: position solver iterations per step */
    float friction;   /* btSoftBody::m_cfg.kDF */
    float margin_m;   /* soft body collision margin (the cloth's thickness) */
} bullet_drape_desc;

/* NULL with err filled when Bullet cannot build the scene. */
bullet_drape *bullet_drape_create(const bullet_drape_desc *d, char *err, size_t err_size);
void bullet_drape_destroy(bullet_drape *b);
/* One step of dt seconds (one Bullet substep). */
void bullet_drape_step(bullet_drape *b, float dt);
int bullet_drape_node_count(const bullet_drape *b);
void bullet_drape_positions(const bullet_drape *b, float *xyz); /* [node][3] */
/* The structural links (row and column neighbours, the ones stretch is measured on). */
int bullet_drape_structural_count(const bullet_drape *b);
void bullet_drape_structural(const bullet_drape *b, int32_t *ends, float *rest); /* [n][2], [n] */
const char *bullet_drape_version(void);

#ifdef __cplusplus
}
#endif

#endif
