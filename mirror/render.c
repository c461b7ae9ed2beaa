/* The one renderer: OpenGL ES 3 into a framebuffer object. The person's depth mesh is drawn
 * first, so its depth buffer hides the garment wherever the person is in front of it. */
#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_private.h"

/* Two-sided Lambert with the light at the camera (a kiosk lit from the screen), per vertex: the
 * garment's 7,000 vertices are finer than its shading varies, and a triangle carries 4 values to
 * interpolate instead of 7 (llvmpipe sets each up per triangle). */
static const char *mesh_vs = "#version 300 es\n"
                             "uniform mat4 u_mvp;\n"
                             "uniform mat4 u_view;\n"
                             "in vec3 a_pos;\n"
                             "in vec3 a_normal;\n"
                             "in vec4 a_rgba;\n"
                             "out vec4 v_rgba;\n"
                             "void main() {\n"
                             "  gl_Position = u_mvp * vec4(a_pos, 1.0);\n"
                             "  float l = abs(normalize(mat3(u_view) * a_normal).z);\n"
                             "  v_rgba = vec4(a_rgba.rgb * (0.3 + 0.7 * l), a_rgba.a);\n"
                             "}\n";
static const char *mesh_fs = "#version 300 es\n"
                             "precision mediump float;\n"
                             "in vec4 v_rgba;\n"
                             "out vec4 o_rgba;\n"
                             "void main() { o_rgba = v_rgba; }\n";
static const char *quad_vs = "#version 300 es\n"
                             "in vec2 a_pos;\n"
                             "in vec2 a_uv;\n"
                             "out vec2 v_uv;\n"
                             "void main() { gl_Position = vec4(a_pos, 0.0, 1.0); v_uv = a_uv; }\n";
static const char *quad_fs = "#version 300 es\n"
                             "precision mediump float;\n"
                             "uniform sampler2D u_tex;\n"
                             "in vec2 v_uv;\n"
                             "out vec4 o_rgba;\n"
                             "void main() { o_rgba = texture(u_tex, v_uv); }\n";

/* The person, per picture pixel: the depth pixel it shows (mirrored), shaded by the normal of the
 * surface around it, and written into the depth buffer at its true depth, so that the garment
 * drawn next is hidden wherever the person is in front of it. The quad covers the depth image's
 * place in the picture and carries each corner's depth pixel (mirrored), so a fragment only
 * truncates its interpolated coordinates: no per-fragment division or bounds test (llvmpipe runs
 * this for every pixel of the picture). */
static const char *person_fs =
    "#version 300 es\n"
    "precision highp float;\n"
    "uniform highp sampler2D u_person;\n" /* per depth pixel: test depth (m), shade */
    "uniform ivec2 u_last;\n"             /* the depth image's last column and row */
    "uniform vec2 u_clip;\n"              /* z_ndc = x + y / z */
    "uniform vec4 u_rgba;\n"
    "in vec2 v_uv;\n" /* depth pixels, from 0 at the image's corner: >= 0 */
    "out vec4 o_rgba;\n"
    "void main() {\n"
    "  vec2 t = texelFetch(u_person, min(ivec2(v_uv), u_last), 0).rg;\n"
    "  if (t.r == 0.0) discard;\n"
    "  gl_FragDepth = 0.5 * (u_clip.x + u_clip.y / t.r) + 0.5;\n"
    "  o_rgba = vec4(u_rgba.rgb * (0.3 + 0.7 * t.g), 1.0);\n"
    "}\n";

#define MIRROR_PERSON_RGBA 0.82f, 0.78f, 0.74f, 1.0f
#define MIRROR_BACKGROUND  0.06f, 0.06f, 0.09f
#define MIRROR_GARMENT_RGBA                                                                        \
    {                                                                                              \
        0.80f, 0.14f, 0.12f, 1.0f                                                                  \
    }
#define MIRROR_BODY_RGBA                                                                           \
    {                                                                                              \
        0.35f, 0.55f, 0.95f, 0.35f                                                                 \
    }
#define MIRROR_PANEL_W 420 /* overlay panel, pixels at scale 1 */
#define MIRROR_PANEL_H 120

/* Buffers keep their storage between frames (glBufferSubData into it): re-specifying them each
 * frame made llvmpipe allocate and fault in fresh pages every frame. */
typedef struct gl_mesh {
    GLuint vao, vbo, ibo;
    GLsizeiptr vbo_bytes, ibo_bytes; /* storage allocated */
    int ni;                          /* indices in the ibo */
} gl_mesh;

struct mirror_renderer {
    int w, h;
    GLuint fbo, colour, depth;
    GLuint target; /* drawn into: fbo, or 0 (the window's back buffer) */
    GLuint mesh_prog, quad_prog, person_prog;
    GLint u_mvp, u_view, u_tex;
    GLint u_person, u_last, u_clip, u_rgba;
    float *person_buf; /* mirror_person_image's */
    int person_cap;
    gl_mesh garment, body;
    GLuint quad_vao, quad_vbo, panel_tex, depth_tex;
    int depth_tex_w, depth_tex_h; /* depth_tex's immutable storage, 0 = none yet */
    mirror_cpu_mesh cpu_garment, cpu_body;
    uint8_t *panel; /* RGBA MIRROR_PANEL_W x MIRROR_PANEL_H */
    uint8_t *rows;  /* glReadPixels' bottom-up RGBA */
};

static GLuint compile(GLenum kind, const char *src, char *err, size_t n)
{
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        snprintf(err, n, "shader does not compile: %s", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

static GLuint program(const char *vs, const char *fs, const char *const *attrs, int nattrs,
                      char *err, size_t n)
{
    GLuint v = compile(GL_VERTEX_SHADER, vs, err, n),
           f = v ? compile(GL_FRAGMENT_SHADER, fs, err, n) : 0;
    if (!f) {
        glDeleteShader(v);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    for (int i = 0; i < nattrs; i++)
        glBindAttribLocation(p, (GLuint)i, attrs[i]);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        snprintf(err, n, "shaders do not link: %s", log);
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

static void mesh_init(gl_mesh *m)
{
    glGenVertexArrays(1, &m->vao);
    glGenBuffers(1, &m->vbo);
    glGenBuffers(1, &m->ibo);
    glBindVertexArray(m->vao);
    glBindBuffer(GL_ARRAY_BUFFER, m->vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m->ibo);
    GLsizei st = sizeof(mirror_vertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, st, (void *)offsetof(mirror_vertex, pos));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, st, (void *)offsetof(mirror_vertex, normal));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, st, (void *)offsetof(mirror_vertex, rgba));
    glBindVertexArray(0);
}

static void mesh_fini(gl_mesh *m)
{
    glDeleteVertexArrays(1, &m->vao);
    glDeleteBuffers(1, &m->vbo);
    glDeleteBuffers(1, &m->ibo);
}

static int targets(mirror_renderer *r, char *err, size_t n)
{
    glGenFramebuffers(1, &r->fbo);
    glGenRenderbuffers(1, &r->colour);
    glGenRenderbuffers(1, &r->depth);
    glBindRenderbuffer(GL_RENDERBUFFER, r->colour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, r->w, r->h);
    glBindRenderbuffer(GL_RENDERBUFFER, r->depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->w, r->h);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->colour);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->depth);
    GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (st != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(err, n, "framebuffer %dx%d incomplete (0x%x)", r->w, r->h, st);
        return -MIRROR_ERR_GL;
    }
    return 0;
}

mirror_renderer *mirror_renderer_create(int width, int height, char *err, size_t n)
{
    if (width < 16 || height < 16 || width > 8192 || height > 8192) {
        snprintf(err, n, "picture %dx%d (16..8192 each)", width, height);
        return NULL;
    }
    mirror_renderer *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(err, n, "out of memory");
        return NULL;
    }
    r->w = width;
    r->h = height;
    r->panel = malloc(MIRROR_PANEL_W * MIRROR_PANEL_H * 4);
    r->rows = malloc((size_t)width * height * 4);
    static const char *const mesh_attrs[] = {"a_pos", "a_normal", "a_rgba"};
    static const char *const quad_attrs[] = {"a_pos", "a_uv"};
    r->mesh_prog = program(mesh_vs, mesh_fs, mesh_attrs, 3, err, n);
    r->quad_prog = r->mesh_prog ? program(quad_vs, quad_fs, quad_attrs, 2, err, n) : 0;
    r->person_prog = r->quad_prog ? program(quad_vs, person_fs, quad_attrs, 2, err, n) : 0;
    if (!r->panel || !r->rows || !r->person_prog || targets(r, err, n) < 0) {
        if (!r->panel || !r->rows)
            snprintf(err, n, "out of memory");
        mirror_renderer_destroy(r);
        return NULL;
    }
    r->target = r->fbo;
    r->u_mvp = glGetUniformLocation(r->mesh_prog, "u_mvp");
    r->u_view = glGetUniformLocation(r->mesh_prog, "u_view");
    r->u_tex = glGetUniformLocation(r->quad_prog, "u_tex");
    r->u_person = glGetUniformLocation(r->person_prog, "u_person");
    r->u_last = glGetUniformLocation(r->person_prog, "u_last");
    r->u_clip = glGetUniformLocation(r->person_prog, "u_clip");
    r->u_rgba = glGetUniformLocation(r->person_prog, "u_rgba");
    mesh_init(&r->garment);
    mesh_init(&r->body);
    glGenVertexArrays(1, &r->quad_vao);
    glGenBuffers(1, &r->quad_vbo);
    glBindVertexArray(r->quad_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->quad_vbo);
    glBufferData(GL_ARRAY_BUFFER, 16 * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), (void *)(2 * sizeof(float)));
    glBindVertexArray(0);
    glGenTextures(1, &r->panel_tex);
    glBindTexture(GL_TEXTURE_2D, r->panel_tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, MIRROR_PANEL_W, MIRROR_PANEL_H);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, n, "OpenGL error 0x%x setting up the renderer", e);
        mirror_renderer_destroy(r);
        return NULL;
    }
    return r;
}

void mirror_renderer_destroy(mirror_renderer *r)
{
    if (!r)
        return;
    if (r->garment.vao) {
        glDeleteTextures(1, &r->depth_tex);
        mesh_fini(&r->garment);
        mesh_fini(&r->body);
        glDeleteVertexArrays(1, &r->quad_vao);
        glDeleteBuffers(1, &r->quad_vbo);
        glDeleteTextures(1, &r->panel_tex);
    }
    glDeleteProgram(r->mesh_prog);
    glDeleteProgram(r->quad_prog);
    glDeleteProgram(r->person_prog);
    glDeleteFramebuffers(1, &r->fbo);
    glDeleteRenderbuffers(1, &r->colour);
    glDeleteRenderbuffers(1, &r->depth);
    mirror_cpu_mesh_free(&r->cpu_garment);
    mirror_cpu_mesh_free(&r->cpu_body);
    free(r->panel);
    free(r->rows);
    free(r->person_buf);
    free(r);
}

/* data into buffer target's storage, grown (by half again) only when it does not fit */
static void upload(GLenum target, GLsizeiptr *cap, GLsizeiptr bytes, const void *data)
{
    if (bytes > *cap) {
        *cap = bytes + bytes / 2;
        glBufferData(target, *cap, NULL, GL_DYNAMIC_DRAW);
    }
    glBufferSubData(target, 0, bytes, data);
}

static void draw(mirror_renderer *r, gl_mesh *g, const mirror_cpu_mesh *m, const float mvp[16],
                 const float view[16])
{
    if (m->ni == 0)
        return;
    glBindVertexArray(g->vao);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    upload(GL_ARRAY_BUFFER, &g->vbo_bytes, (GLsizeiptr)m->nv * (GLsizeiptr)sizeof *m->v, m->v);
    if (m->idx_changed || g->ni != m->ni) { /* triangles change only with the topology */
        upload(GL_ELEMENT_ARRAY_BUFFER, &g->ibo_bytes,
               (GLsizeiptr)m->ni * (GLsizeiptr)sizeof *m->idx, m->idx);
        g->ni = m->ni;
    }
    glUniformMatrix4fv(r->u_mvp, 1, GL_TRUE, mvp);
    glUniformMatrix4fv(r->u_view, 1, GL_TRUE, view);
    glDrawElements(GL_TRIANGLES, m->ni, GL_UNSIGNED_INT, 0);
}

static void quad(mirror_renderer *r, const float xyuv[16])
{
    glBindVertexArray(r->quad_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->quad_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, 16 * sizeof *xyuv, xyuv);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

static int person(mirror_renderer *r, const mirror_depth *d, const float proj[16])
{
    const float *image = d->person;
    if (!image) {
        if (mirror_person_image(d, &r->person_buf, &r->person_cap) < 0)
            return -MIRROR_ERR_NO_MEMORY;
        image = r->person_buf;
    }
    float s, offx;
    mirror_picture_fit(d, r->w, r->h, &s, &offx);
    glActiveTexture(GL_TEXTURE0);
    if (d->width != r->depth_tex_w || d->height != r->depth_tex_h) {
        /* immutable storage, made again only when the depth image's size changes: re-specifying
         * 2.4 MB each frame cost llvmpipe fresh pages every frame */
        glDeleteTextures(1, &r->depth_tex);
        glGenTextures(1, &r->depth_tex);
        glBindTexture(GL_TEXTURE_2D, r->depth_tex);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RG32F, d->width, d->height);
        r->depth_tex_w = d->width;
        r->depth_tex_h = d->height;
    }
    glBindTexture(GL_TEXTURE_2D, r->depth_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, d->width, d->height, GL_RG, GL_FLOAT, image);
    glUseProgram(r->person_prog);
    glUniform1i(r->u_person, 0);
    glUniform2i(r->u_last, d->width - 1, d->height - 1);
    glUniform2f(r->u_clip, proj[10], proj[11]);
    glUniform4f(r->u_rgba, MIRROR_PERSON_RGBA);
    /* picture pixel x shows depth column (w - x - offx) / s - 1/2 (mirror_projection): the left
     * edge of the image's place shows the far edge of the last column, the right edge column 0;
     * rows run top to bottom, the picture's y bottom to top */
    float x0 = 2.0f * offx / (float)r->w - 1.0f, x1 = 2.0f * (offx + s * d->width) / r->w - 1.0f;
    float u = (float)d->width, v = (float)d->height;
    const float xyuv[16] = {x0, -1, u, v, x1, -1, 0, v, x0, 1, u, 0, x1, 1, 0, 0};
    quad(r, xyuv);
    return 0;
}

/* The overlay: text rasterised into a small RGBA panel, drawn over the top-left corner. */
static void overlay(mirror_renderer *r, const char *text, int fit_map)
{
    memset(r->panel, 0, MIRROR_PANEL_W * MIRROR_PANEL_H * 4);
    static const uint8_t white[4] = {255, 255, 255, 255};
    int y = 4, lines = 0, widest = 0;
    const char *p = text;
    while (*p && y + MIRROR_FONT_H <= MIRROR_PANEL_H) {
        char line[96];
        size_t k = strcspn(p, "\n");
        snprintf(line, sizeof line, "%.*s", (int)(k < 95 ? k : 95), p);
        int w = mirror_text(r->panel, MIRROR_PANEL_W, MIRROR_PANEL_H, 4, y, 1, line, white);
        widest = w > widest ? w : widest;
        y += MIRROR_FONT_H;
        lines++;
        p += k + (p[k] == '\n');
    }
    if (fit_map && y + 6 <= MIRROR_PANEL_H) { /* the ramp, 0 to the limit, left to right */
        for (int x = 0; x < 100; x++) {
            float rgb[3];
            mirror_fit_colour(MIRROR_FIT_MAP_LIMIT * (float)x / 99.0f, rgb);
            for (int yy = y; yy < y + 5; yy++) {
                uint8_t *q = &r->panel[(yy * MIRROR_PANEL_W + 4 + x) * 4];
                q[0] = (uint8_t)(rgb[0] * 255);
                q[1] = (uint8_t)(rgb[1] * 255);
                q[2] = (uint8_t)(rgb[2] * 255);
                q[3] = 255;
            }
        }
        y += 7;
        widest = widest > 104 ? widest : 104;
    }
    (void)lines;
    int pw = widest + 8, ph = y + 2 < MIRROR_PANEL_H ? y + 2 : MIRROR_PANEL_H;
    for (int yy = 0; yy < ph; yy++) /* a dark backing behind the text */
        for (int x = 0; x < pw; x++) {
            uint8_t *q = &r->panel[(yy * MIRROR_PANEL_W + x) * 4];
            if (q[3] == 0)
                q[3] = 150;
        }
    int scale = r->h >= 600 ? 2 : 1;
    glBindTexture(GL_TEXTURE_2D, r->panel_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, MIRROR_PANEL_W, ph, GL_RGBA, GL_UNSIGNED_BYTE,
                    r->panel); /* the rows drawn on: the quad samples no others */
    float x0 = -1.0f, y0 = 1.0f, x1 = -1.0f + 2.0f * (float)(pw * scale) / (float)r->w;
    float y1 = 1.0f - 2.0f * (float)(ph * scale) / (float)r->h;
    float u1 = (float)pw / MIRROR_PANEL_W, v1 = (float)ph / MIRROR_PANEL_H;
    const float xyuv[] = {x0, y0, 0, 0, x1, y0, u1, 0, x0, y1, 0, v1, x1, y1, u1, v1};
    glUseProgram(r->quad_prog);
    glUniform1i(r->u_tex, 0);
    glActiveTexture(GL_TEXTURE0);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    quad(r, xyuv);
    glDisable(GL_BLEND);
}

int mirror_render(mirror_renderer *r, const mirror_view *v, char *err, size_t n)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->target);
    glViewport(0, 0, r->w, r->h);
    glClearColor(MIRROR_BACKGROUND, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (v->depth) {
        float proj[16], w2c[16], mvp[16];
        mirror_projection(v->depth, r->w, r->h, proj);
        mirror_world_to_camera(v->depth->camera_to_world, w2c);
        mirror_mat_mul(proj, w2c, mvp);
        glEnable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE); /* the mirror flip turns every winding around */
        glDepthFunc(GL_ALWAYS);  /* the person is first over the cleared picture: no test */
        if (person(r, v->depth, proj) < 0) {
            snprintf(err, n, "out of memory for the person's image");
            return -MIRROR_ERR_NO_MEMORY;
        }
        glDepthFunc(GL_LESS);
        glUseProgram(r->mesh_prog);
        if (v->garment) {
            float rgba[4] = MIRROR_GARMENT_RGBA;
            if (v->garment_rgb[0] + v->garment_rgb[1] + v->garment_rgb[2] > 0.0f)
                memcpy(rgba, v->garment_rgb, sizeof v->garment_rgb);
            int rc = mirror_world_mesh(v->garment, rgba, v->fit_map, &r->cpu_garment);
            if (rc < 0) {
                snprintf(err, n, "garment mesh: %s", mirror_error_text(rc));
                return rc;
            }
            draw(r, &r->garment, &r->cpu_garment, mvp, w2c);
        }
        if (v->body) {
            const float rgba[4] = MIRROR_BODY_RGBA;
            if (mirror_world_mesh(v->body, rgba, 0, &r->cpu_body) == 0) {
                glEnable(GL_BLEND);
                glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
                glDepthMask(GL_FALSE);
                draw(r, &r->body, &r->cpu_body, mvp, w2c);
                glDepthMask(GL_TRUE);
                glDisable(GL_BLEND);
            }
        }
    }
    if (v->overlay_text)
        overlay(r, v->overlay_text, v->fit_map);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, n, "OpenGL error 0x%x while drawing", e);
        return -MIRROR_ERR_GL;
    }
    return 0;
}

int mirror_read_rgb(mirror_renderer *r, uint8_t *rgb)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->target);
    glReadPixels(0, 0, r->w, r->h, GL_RGBA, GL_UNSIGNED_BYTE, r->rows);
    for (int y = 0; y < r->h; y++) { /* GL's rows run bottom to top */
        const uint8_t *src = r->rows + (size_t)(r->h - 1 - y) * r->w * 4;
        uint8_t *dst = rgb + (size_t)y * r->w * 3;
        for (int x = 0; x < r->w; x++) {
            dst[x * 3 + 0] = src[x * 4 + 0];
            dst[x * 3 + 1] = src[x * 4 + 1];
            dst[x * 3 + 2] = src[x * 4 + 2];
        }
    }
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void mirror_present(mirror_renderer *r, int window_w, int window_h)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    /* the picture's aspect kept: scaled to fit, centred */
    float s = (float)window_w / (float)r->w < (float)window_h / (float)r->h
                  ? (float)window_w / (float)r->w
                  : (float)window_h / (float)r->h;
    int w = (int)((float)r->w * s), h = (int)((float)r->h * s);
    int x = (window_w - w) / 2, y = (window_h - h) / 2;
    glBlitFramebuffer(0, 0, r->w, r->h, x, y, x + w, y + h, GL_COLOR_BUFFER_BIT,
                      w == r->w && h == r->h ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
}

void mirror_renderer_draw_to_window(mirror_renderer *r, int window)
{
    r->target = window ? 0 : r->fbo;
}

unsigned mirror_renderer_fbo(const mirror_renderer *r)
{
    return r->fbo;
}
