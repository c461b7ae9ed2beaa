/* A scene whose picture is known from geometry alone: a torso plane with an arm in front of it,
 * seen by a 640x480 depth camera, and a garment plane between the two; published over the bus
 * until tryon-mirror has drawn it. */
#ifndef TRYON_TEST_MIRROR_SCENE_H
#define TRYON_TEST_MIRROR_SCENE_H

#include <sys/types.h>

#include "bus.h"

enum { MS_BACKGROUND, MS_PERSON, MS_GARMENT };
#define MS_W 640
#define MS_H 480

/* What the mirror must show at picture pixel (px, py), from the geometry (mirrored view). */
int ms_expected(int px, int py);
/* Publishes the scene's DEPTH then CLOTH every 100 ms until pid exits (or timeout_ms); returns
 * its exit status as ts_wait does. */
int ms_serve_until_exit(pid_t pid, int timeout_ms);
/* The garment colour as the renderer shades it: red dominant. */
int ms_classify(const unsigned char *rgb);

#endif
