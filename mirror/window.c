/* The kiosk window: SDL2 with an OpenGL ES 3 context. The renderer draws straight into the back
 * buffer when the window is the picture's size; otherwise into its framebuffer object, which
 * mirror_present scales into the window. */
#include <EGL/egl.h>
#include <SDL2/SDL.h>
#include <stdio.h>
#include <string.h>

#include "mirror.h"

struct mirror_window {
    SDL_Window *win;
    SDL_GLContext ctx;
};

mirror_window *mirror_window_create(int width, int height, int kiosk, char *err, size_t n)
{
    /* On X11, SDL's own choice: GLX, where Mesa's software renderer keeps the picture in memory
     * shared with the X server (MIT-SHM). Through EGL it sends every picture over the socket
     * (1.2 MB at 640x480), which costs the X server (Xvfb) about 4 times the CPU (docs/mirror.md,
     * "The window under Xvfb"). SDL falls back to EGL where GLX has no OpenGL ES context. */
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        snprintf(err, n, "no display (%s): run with --headless --out DIR, or set DISPLAY",
                 SDL_GetError());
        return NULL;
    }
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_ES);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 0);
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    /* the renderer may draw straight into the back buffer: the same depth bits as its own
     * framebuffer object (SDL's default is 16), or the occlusion test would differ */
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
    Uint32 flags = SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE;
    if (kiosk)
        flags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
    mirror_window *w = SDL_calloc(1, sizeof *w);
    if (w)
        w->win = SDL_CreateWindow("tryon mirror", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                  width, height, flags);
    if (w && w->win)
        w->ctx = SDL_GL_CreateContext(w->win);
    if (!w || !w->win || !w->ctx) {
        snprintf(err, n, "no OpenGL ES 3 window (%s): try --headless --out DIR", SDL_GetError());
        mirror_window_destroy(w);
        return NULL;
    }
    SDL_GL_SetSwapInterval(0); /* latency over tearing: frames come at the camera's pace */
    if (kiosk)
        SDL_ShowCursor(SDL_DISABLE);
    return w;
}

void mirror_window_destroy(mirror_window *w)
{
    if (w) {
        if (w->ctx)
            SDL_GL_DeleteContext(w->ctx);
        if (w->win)
            SDL_DestroyWindow(w->win);
        SDL_free(w);
    }
    SDL_Quit();
}

static mirror_key key_of(SDL_Keycode k)
{
    switch (k) {
    case SDLK_RIGHT:
    case SDLK_n:
        return MIRROR_KEY_NEXT;
    case SDLK_LEFT:
    case SDLK_p:
        return MIRROR_KEY_PREVIOUS;
    case SDLK_UP:
    case SDLK_PLUS:
    case SDLK_EQUALS:
        return MIRROR_KEY_SIZE_UP;
    case SDLK_DOWN:
    case SDLK_MINUS:
        return MIRROR_KEY_SIZE_DOWN;
    case SDLK_o:
        return MIRROR_KEY_OVERLAY;
    case SDLK_f:
        return MIRROR_KEY_FIT_MAP;
    case SDLK_b:
        return MIRROR_KEY_BODY;
    case SDLK_q:
    case SDLK_ESCAPE:
        return MIRROR_KEY_QUIT;
    default:
        return MIRROR_KEY_NONE;
    }
}

mirror_key mirror_window_poll(mirror_window *w)
{
    (void)w;
    SDL_Event e;
    while (SDL_PollEvent(&e)) {
        if (e.type == SDL_QUIT)
            return MIRROR_KEY_QUIT;
        if (e.type == SDL_KEYDOWN) {
            mirror_key k = key_of(e.key.keysym.sym);
            if (k != MIRROR_KEY_NONE)
                return k;
        }
    }
    return MIRROR_KEY_NONE;
}

void mirror_window_size(mirror_window *w, int *width, int *height)
{
    SDL_GL_GetDrawableSize(w->win, width, height);
}

void mirror_window_swap(mirror_window *w)
{
    SDL_GL_SwapWindow(w->win);
}

const char *mirror_window_presents(mirror_window *w)
{
    (void)w;
    /* SDL on Wayland, or forced to EGL (SDL_VIDEO_X11_FORCE_EGL=1), has an EGL context */
    int egl = eglGetCurrentContext() != EGL_NO_CONTEXT;
    /* System V shared memory mapped: llvmpipe's picture, which the X server reads (MIT-SHM) */
    int shared = 0;
    FILE *f = fopen("/proc/self/maps", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        shared += strstr(line, "SYSV") != NULL;
    if (f)
        fclose(f);
    if (shared)
        return egl ? "through EGL, the picture in memory shared with the X server"
                   : "through GLX, the picture in memory shared with the X server";
    /* a GPU's driver (DRI3) shares buffers otherwise; llvmpipe on X11 then sends each picture */
    return egl ? "through EGL, no System V memory shared (llvmpipe on X11: each picture sent)"
               : "through GLX, no System V memory shared (llvmpipe on X11: each picture sent)";
}
