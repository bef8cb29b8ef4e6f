/*
 * What a C renderer with an animated mesh does with smoothtri.h: builds an updatable scene
 * (ST_BUILD_UPDATABLE) once, then moves its vertices every frame with st_scene_update, in
 * float and in double, and checks each frame alone:
 *   - the mesh is a unit sphere's, moved each frame by a scale and a translation, so every hit
 *     lies on the frame's analytic sphere within its t_error;
 *   - every hit equals that of a fresh st_scene_build of the same vertices within t_error (bit
 *     for bit when the update built the tree anew);
 *   - a frame that collapses every vertex to one point succeeds with a scene that every ray
 *     misses, and the next frame hits again;
 *   - bad updates (NULL, a fixed scene, another vertex count, a NaN, a bad stride) return their
 *     status and leave the scene as it was: the same hits bit for bit.
 * Prints "all checks passed" when every check held.
 */
#include "smoothtri.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

#define PI 3.14159265358979323846
#define RINGS 12
#define SEGMENTS 24
#define RAYS 64
#define FRAMES 12

typedef struct { float p[3], n[3]; } vertex_f;
typedef struct { double p[3], n[3]; } vertex_d;

static size_t vertex_count, triangle_count;
static vertex_d *rest;
static uint32_t *idx;

/* A latitude-longitude unit sphere with radial normals: its patches are the sphere exactly. */
static void sphere(void) {
    unsigned i, j, k = 0;
    vertex_count = 2 + (size_t)(RINGS - 1) * SEGMENTS;
    triangle_count = 2 * (size_t)SEGMENTS * (RINGS - 1);
    rest = (vertex_d *)calloc(vertex_count, sizeof(vertex_d));
    idx = (uint32_t *)calloc(3 * triangle_count, sizeof(uint32_t));
    rest[0].p[2] = 1;
    rest[1].p[2] = -1;
    for (i = 1; i < RINGS; i++) {
        for (j = 0; j < SEGMENTS; j++) {
            double th = PI * i / RINGS, ph = 2 * PI * j / SEGMENTS;
            vertex_d *x = &rest[2 + (i - 1) * SEGMENTS + j];
            x->p[0] = sin(th) * cos(ph);
            x->p[1] = sin(th) * sin(ph);
            x->p[2] = cos(th);
        }
    }
    for (i = 0; i < vertex_count; i++) memcpy(rest[i].n, rest[i].p, sizeof rest[i].n);
#define RING(i, j) (uint32_t)(2 + ((i) - 1) * SEGMENTS + (j) % SEGMENTS)
    for (j = 0; j < SEGMENTS; j++) {
        uint32_t *t = &idx[3 * k++];
        t[0] = 0; t[1] = RING(1, j); t[2] = RING(1, j + 1);
        t = &idx[3 * k++];
        t[0] = 1; t[1] = RING(RINGS - 1, j + 1); t[2] = RING(RINGS - 1, j);
    }
    for (i = 1; i + 1 < RINGS; i++) {
        for (j = 0; j < SEGMENTS; j++) {
            uint32_t *t = &idx[3 * k++];
            t[0] = RING(i, j); t[1] = RING(i + 1, j); t[2] = RING(i + 1, j + 1);
            t = &idx[3 * k++];
            t[0] = RING(i, j); t[1] = RING(i + 1, j + 1); t[2] = RING(i, j + 1);
        }
    }
#undef RING
}

/* Frame f's sphere: radius and centre (frame -1: every vertex at one point). */
static void frame_sphere(int f, double *radius, double c[3]) {
    if (f < 0) {
        *radius = 0;
    } else {
        *radius = 0.5 + 0.1 * f;
    }
    c[0] = 0.3 * sin(0.7 * f);
    c[1] = 0.2 * cos(1.3 * f);
    c[2] = 0.1 * f - 0.5;
}

static void pose_d(int f, vertex_d *out) {
    double r, c[3];
    size_t i;
    unsigned k;
    frame_sphere(f, &r, c);
    for (i = 0; i < vertex_count; i++) {
        for (k = 0; k < 3; k++) {
            out[i].p[k] = c[k] + r * rest[i].p[k];
            out[i].n[k] = rest[i].n[k];
        }
    }
}

static void pose_f(int f, vertex_f *out, vertex_d *scratch) {
    size_t i;
    unsigned k;
    pose_d(f, scratch);
    for (i = 0; i < vertex_count; i++) {
        for (k = 0; k < 3; k++) {
            out[i].p[k] = (float)scratch[i].p[k];
            out[i].n[k] = (float)scratch[i].n[k];
        }
    }
}

/* Ray k toward frame f's sphere: from a point at distance 5 from its centre, aimed near it. */
static void ray_k(int f, unsigned k, double o[3], double d[3]) {
    double r, c[3];
    double a = 2 * PI * k / RAYS * 5.0, b = acos(1 - 2 * (k + 0.5) / RAYS);
    frame_sphere(f < 0 ? 0 : f, &r, c);
    o[0] = c[0] + 5 * sin(b) * cos(a);
    o[1] = c[1] + 5 * sin(b) * sin(a);
    o[2] = c[2] + 5 * cos(b);
    d[0] = c[0] + 0.4 * sin(1.7 * k) - o[0];
    d[1] = c[1] + 0.4 * cos(2.3 * k) - o[1];
    d[2] = c[2] + 0.2 * sin(0.7 * k) - o[2];
}

/* The ray's first crossing with the sphere (radius r, centre c), or -1. */
static double sphere_t(const double o[3], const double d[3], double r, const double c[3]) {
    double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
    double disc = b * b - a * cc;
    if (disc < 0) return -1;
    return (-b - sqrt(disc)) / a;
}

static st_rayhit ray_f(int f, unsigned k) {
    double o[3], d[3];
    st_rayhit rh;
    memset(&rh, 0, sizeof rh);
    ray_k(f, k, o, d);
    rh.ray.org_x = (float)o[0]; rh.ray.org_y = (float)o[1]; rh.ray.org_z = (float)o[2];
    rh.ray.dir_x = (float)d[0]; rh.ray.dir_y = (float)d[1]; rh.ray.dir_z = (float)d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = INFINITY;
    return rh;
}

static st_rayhit_f64 ray_d(int f, unsigned k) {
    double o[3], d[3];
    st_rayhit_f64 rh;
    memset(&rh, 0, sizeof rh);
    ray_k(f, k, o, d);
    rh.ray.org_x = o[0]; rh.ray.org_y = o[1]; rh.ray.org_z = o[2];
    rh.ray.dir_x = d[0]; rh.ray.dir_y = d[1]; rh.ray.dir_z = d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = INFINITY;
    return rh;
}

/* The hits of frame f's rays in a float scene. */
static void trace_f(const st_scene *s, int f, st_rayhit *out) {
    unsigned k;
    for (k = 0; k < RAYS; k++) {
        out[k] = ray_f(f, k);
        st_intersect1(s, &out[k]);
    }
}

static void trace_d(const st_scene_f64 *s, int f, st_rayhit_f64 *out) {
    unsigned k;
    for (k = 0; k < RAYS; k++) {
        out[k] = ray_d(f, k);
        st_intersect1_f64(s, &out[k]);
    }
}

static int same_f(const st_rayhit *a, const st_rayhit *b) {
    return memcmp(&a->ray.tfar, &b->ray.tfar, sizeof(float)) == 0 &&
           a->hit.prim_id == b->hit.prim_id &&
           memcmp(&a->hit.t_error, &b->hit.t_error, sizeof(float)) == 0;
}

/* Checks frame f's float hits against its analytic sphere and a fresh build's hits. */
static void check_frame_f(int f, const st_rayhit *got, const st_rayhit *fresh, int refitted) {
    unsigned k, hits = 0;
    double r, c[3];
    frame_sphere(f, &r, c);
    for (k = 0; k < RAYS; k++) {
        double o[3], d[3], t;
        const st_rayhit *h = &got[k];
        ray_k(f, k, o, d);
        t = sphere_t(o, d, r, c);
        if (f < 0) {
            CHECK(h->hit.geom_id == ST_INVALID_ID);
            continue;
        }
        /* Rays graze the sphere only at tangency; the mesh's edge rings meet it exactly. */
        if (t > 0 && h->hit.geom_id != ST_INVALID_ID) {
            hits++;
            /* The certified bound plus the float rounding of the ray and the vertices. */
            CHECK(fabs(h->ray.tfar - t) <= h->hit.t_error + 1e-5 * (1 + t));
        }
        CHECK((h->hit.geom_id == ST_INVALID_ID) == (fresh[k].hit.geom_id == ST_INVALID_ID));
        if (h->hit.geom_id != ST_INVALID_ID && fresh[k].hit.geom_id != ST_INVALID_ID) {
            CHECK(fabs(h->ray.tfar - fresh[k].ray.tfar) <=
                  h->hit.t_error + fresh[k].hit.t_error);
            if (!refitted) CHECK(same_f(h, &fresh[k]));
        }
    }
    if (f >= 0) CHECK(hits > RAYS / 4);
}

static void check_frame_d(int f, const st_rayhit_f64 *got, const st_rayhit_f64 *fresh,
                          int refitted) {
    unsigned k, hits = 0;
    double r, c[3];
    frame_sphere(f, &r, c);
    for (k = 0; k < RAYS; k++) {
        double o[3], d[3], t;
        const st_rayhit_f64 *h = &got[k];
        ray_k(f, k, o, d);
        t = sphere_t(o, d, r, c);
        if (f < 0) {
            CHECK(h->hit.geom_id == ST_INVALID_ID);
            continue;
        }
        if (t > 0 && h->hit.geom_id != ST_INVALID_ID) {
            hits++;
            CHECK(fabs(h->ray.tfar - t) <= h->hit.t_error + 1e-12 * (1 + t));
        }
        CHECK((h->hit.geom_id == ST_INVALID_ID) == (fresh[k].hit.geom_id == ST_INVALID_ID));
        if (h->hit.geom_id != ST_INVALID_ID && fresh[k].hit.geom_id != ST_INVALID_ID) {
            CHECK(fabs(h->ray.tfar - fresh[k].ray.tfar) <=
                  h->hit.t_error + fresh[k].hit.t_error);
            if (!refitted) CHECK(h->ray.tfar == fresh[k].ray.tfar);
        }
    }
    if (f >= 0) CHECK(hits > RAYS / 4);
}

/* A fresh build of frame f's float vertices (flags without ST_BUILD_UPDATABLE). */
static st_scene *fresh_f(const vertex_f *v, uint32_t flags, void **memory) {
    size_t bytes = 0;
    st_scene *s = NULL;
    CHECK(st_scene_required_bytes(vertex_count, triangle_count, flags, &bytes) == ST_OK);
    *memory = malloc(bytes);
    CHECK(st_scene_build(*memory, bytes, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                         vertex_count, idx, triangle_count, flags, 8, &s) == ST_OK);
    return s;
}

static void run_f(uint32_t flags) {
    size_t bytes = 0;
    void *memory;
    st_scene *s = NULL;
    st_scene_info info;
    vertex_f *v = (vertex_f *)calloc(vertex_count, sizeof(vertex_f));
    vertex_d *scratch = (vertex_d *)calloc(vertex_count, sizeof(vertex_d));
    st_rayhit got[RAYS], fresh[RAYS], again[RAYS];
    int f;

    pose_f(0, v, scratch);
    CHECK(st_scene_required_bytes(vertex_count, triangle_count, flags | ST_BUILD_UPDATABLE,
                                  &bytes) == ST_OK);
    memory = malloc(bytes);
    CHECK(st_scene_build(memory, bytes, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                         vertex_count, idx, triangle_count, flags | ST_BUILD_UPDATABLE, 8,
                         &s) == ST_OK);
    CHECK(st_scene_get_info(s, &info) == ST_OK);
    CHECK(info.bytes_used <= bytes && info.update_count == 0);
    for (f = 1; f <= FRAMES; f++) {
        void *fm;
        st_scene *fs;
        int pose = f == FRAMES / 2 ? -1 : f;
        pose_f(pose, v, scratch);
        CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                              vertex_count) == ST_OK);
        CHECK(st_scene_get_info(s, &info) == ST_OK);
        CHECK(info.update_count == (uint32_t)f);
        CHECK(info.triangle_count == triangle_count);
        trace_f(s, pose, got);
        if (pose < 0) {
            CHECK(info.rejected_count == triangle_count);
            check_frame_f(pose, got, got, 1);
            continue;
        }
        CHECK(info.rejected_count == 0);
        fs = fresh_f(v, flags, &fm);
        trace_f(fs, pose, fresh);
        check_frame_f(pose, got, fresh, (int)info.bvh_refitted);
        free(fm);
    }

    /* Bad updates leave the scene as it was. */
    trace_f(s, FRAMES, got);
    CHECK(st_scene_update(NULL, v[0].p, 0, v[0].n, 0, vertex_count) == ST_ERROR_NULL_ARGUMENT);
    CHECK(st_scene_update(s, NULL, 0, v[0].n, 0, vertex_count) == ST_ERROR_NULL_ARGUMENT);
    CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                          vertex_count - 1) == ST_ERROR_INVALID_ARGUMENT);
    CHECK(st_scene_update(s, v[0].p, 8, v[0].n, sizeof(vertex_f), vertex_count) ==
          ST_ERROR_INVALID_ARGUMENT);
    pose_f(3, v, scratch);
    v[vertex_count / 2].p[1] = NAN;
    CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                          vertex_count) == ST_ERROR_NON_FINITE);
    v[vertex_count / 2].p[1] = 0;
    v[3].n[0] = INFINITY;
    CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                          vertex_count) == ST_ERROR_NON_FINITE);
    CHECK(st_scene_update_f64((st_scene_f64 *)(void *)s, scratch[0].p, sizeof(vertex_d),
                              scratch[0].n, sizeof(vertex_d), vertex_count) ==
          ST_ERROR_WRONG_SCENE);
    CHECK(st_scene_get_info(s, &info) == ST_OK);
    CHECK(info.update_count == FRAMES);
    trace_f(s, FRAMES, again);
    {
        unsigned k;
        for (k = 0; k < RAYS; k++) CHECK(same_f(&got[k], &again[k]));
    }

    /* A scene built without the flag cannot be updated. */
    {
        void *fm;
        st_scene *fs;
        pose_f(1, v, scratch);
        fs = fresh_f(v, flags, &fm);
        CHECK(st_scene_update(fs, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                              vertex_count) == ST_ERROR_NOT_UPDATABLE);
        free(fm);
    }
    free(memory);
    free(v);
    free(scratch);
}

static void run_d(uint32_t flags) {
    size_t bytes = 0, fbytes = 0;
    void *memory, *fm;
    st_scene_f64 *s = NULL, *fs = NULL;
    st_scene_info info;
    vertex_d *v = (vertex_d *)calloc(vertex_count, sizeof(vertex_d));
    st_rayhit_f64 got[RAYS], fresh[RAYS];
    int f;

    pose_d(0, v);
    CHECK(st_scene_required_bytes_f64(vertex_count, triangle_count, flags | ST_BUILD_UPDATABLE,
                                      &bytes) == ST_OK);
    memory = malloc(bytes);
    CHECK(st_scene_build_f64(memory, bytes, v[0].p, sizeof(vertex_d), v[0].n,
                             sizeof(vertex_d), vertex_count, idx, triangle_count,
                             flags | ST_BUILD_UPDATABLE, 8, &s) == ST_OK);
    CHECK(st_scene_required_bytes_f64(vertex_count, triangle_count, flags, &fbytes) == ST_OK);
    fm = malloc(fbytes);
    for (f = 1; f <= FRAMES; f++) {
        pose_d(f, v);
        CHECK(st_scene_update_f64(s, v[0].p, sizeof(vertex_d), v[0].n, sizeof(vertex_d),
                                  vertex_count) == ST_OK);
        CHECK(st_scene_get_info_f64(s, &info) == ST_OK);
        CHECK(info.update_count == (uint32_t)f);
        CHECK(st_scene_build_f64(fm, fbytes, v[0].p, sizeof(vertex_d), v[0].n,
                                 sizeof(vertex_d), vertex_count, idx, triangle_count, flags, 8,
                                 &fs) == ST_OK);
        trace_d(s, f, got);
        trace_d(fs, f, fresh);
        check_frame_d(f, got, fresh, (int)info.bvh_refitted);
    }
    CHECK(st_scene_update_f64(fs, v[0].p, 0, v[0].n, 0, vertex_count) ==
          ST_ERROR_NOT_UPDATABLE);
    free(fm);
    free(memory);
    free(v);
}

int main(void) {
    uint32_t flags;
    sphere();
    for (flags = 0; flags < 4; flags++) {
        run_f(flags);
        run_d(flags);
    }
    free(rest);
    free(idx);
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("all checks passed\n");
    return 0;
}
