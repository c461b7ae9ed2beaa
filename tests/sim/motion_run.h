/* The shirt on a real-motion scene from rest, checked against issue 19's goals (motion_run.c). */
#ifndef TRYON_TESTS_MOTION_RUN_H
#define TRYON_TESTS_MOTION_RUN_H

/* the bench's body; the shirt at test size (the 7,000-vertex shirt's figures hold at it) */
#define BODY_VERTS  6000
#define SHIRT_VERTS 2000
#define FPS         30.0

/* frames of motion from rest on each backend: every frame solved (not carried), nothing over
   1 mm inside, max strain never over 10 %, and after the first second within 3 % max, 1 % p99 */
void run_motion(const char *motion, int frames);

#endif
