/* An OpenGL ES 3 context with no display at all: Mesa's surfaceless EGL platform. The renderer
 * draws into its own framebuffer object, so no window surface is needed. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <stdio.h>
#include <stdlib.h>

#include "mirror.h"

struct mirror_gl {
    EGLDisplay dpy;
    EGLContext ctx;
};

mirror_gl *mirror_gl_headless(char *err, size_t n)
{
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!get_display) {
        snprintf(err, n, "EGL has no eglGetPlatformDisplayEXT (EGL_EXT_platform_base)");
        return NULL;
    }
    EGLDisplay dpy = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint major = 0, minor = 0;
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) {
        snprintf(err, n,
                 "EGL's surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA) does not open "
                 "(error 0x%x): is Mesa's libegl-mesa0 installed?",
                 eglGetError());
        return NULL;
    }
    static const EGLint config_attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                          EGL_OPENGL_ES3_BIT, EGL_NONE};
    static const EGLint ctx_attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    EGLConfig cfg;
    EGLint count = 0;
    EGLContext ctx = EGL_NO_CONTEXT;
    if (eglBindAPI(EGL_OPENGL_ES_API) && eglChooseConfig(dpy, config_attrs, &cfg, 1, &count) &&
        count > 0)
        ctx = eglCreateContext(dpy, cfg, EGL_NO_CONTEXT, ctx_attrs);
    if (ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        snprintf(err, n, "no OpenGL ES 3 context on EGL %d.%d (error 0x%x)", major, minor,
                 eglGetError());
        if (ctx != EGL_NO_CONTEXT)
            eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return NULL;
    }
    mirror_gl *g = malloc(sizeof *g);
    if (!g) {
        snprintf(err, n, "out of memory");
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return NULL;
    }
    g->dpy = dpy;
    g->ctx = ctx;
    return g;
}

void mirror_gl_destroy(mirror_gl *g)
{
    if (!g)
        return;
    eglMakeCurrent(g->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(g->dpy, g->ctx);
    /* No eglTerminate: Mesa 22.3 unloads its driver there and loses a table it initialised once
     * (128 bytes, LeakSanitizer in every run). The display belongs to the process; what is left
     * of it goes with the process. */
    free(g);
}
