/* What the C test programs share beside their checks (check.h): a latitude-longitude unit
 * sphere, whose patches with radial normals are the sphere exactly, and a float scene built
 * into memory of its own. */
#ifndef SMOOTHTRI_TEST_COMMON_H
#define SMOOTHTRI_TEST_COMMON_H

#include "smoothtri.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"

#define PI 3.14159265358979323846

/* The unit sphere of `rings` rings of `segments` segments (at least 2 and 3): its vertex and
 * triangle counts, its vertices (`*points`: x, y, z each, the two poles first, then ring after
 * ring; a vertex's radial normal is its position) and its triangles (`*idx`: three indices
 * each, counter-clockwise seen from outside), both allocated here and freed by the caller. */
static inline void unit_sphere(unsigned rings, unsigned segments, size_t *vertex_count,
                               size_t *triangle_count, double **points, uint32_t **idx) {
    unsigned i, j, k = 0;
    size_t vc = 2 + (size_t)(rings - 1) * segments, tc = 2 * (size_t)segments * (rings - 1);
    double *p = (double *)calloc(3 * vc, sizeof(double));
    uint32_t *t;
    *vertex_count = vc;
    *triangle_count = tc;
    *points = p;
    *idx = (uint32_t *)calloc(3 * tc, sizeof(uint32_t));
    p[2] = 1; /* north pole */
    p[5] = -1; /* south pole */
    for (i = 1; i < rings; i++) {
        for (j = 0; j < segments; j++) {
            double th = PI * i / rings, ph = 2 * PI * j / segments;
            double *x = &p[3 * (2 + (i - 1) * segments + j)];
            x[0] = sin(th) * cos(ph);
            x[1] = sin(th) * sin(ph);
            x[2] = cos(th);
        }
    }
#define RING(i, j) (uint32_t)(2 + ((i) - 1) * segments + (j) % segments)
    for (j = 0; j < segments; j++) {
        t = &(*idx)[3 * k++];
        t[0] = 0; t[1] = RING(1, j); t[2] = RING(1, j + 1);
        t = &(*idx)[3 * k++];
        t[0] = 1; t[1] = RING(rings - 1, j + 1); t[2] = RING(rings - 1, j);
    }
    for (i = 1; i + 1 < rings; i++) {
        for (j = 0; j < segments; j++) {
            t = &(*idx)[3 * k++];
            t[0] = RING(i, j); t[1] = RING(i + 1, j); t[2] = RING(i + 1, j + 1);
            t = &(*idx)[3 * k++];
            t[0] = RING(i, j); t[1] = RING(i + 1, j + 1); t[2] = RING(i, j + 1);
        }
    }
#undef RING
}

/* A float scene of `vertex_count` interleaved vertices (positions at `p`, normals at `n`,
 * `stride` bytes apart) built with `flags` and `iterations` into memory of its own, as long as
 * st_scene_required_bytes says: `*memory` (freed by the caller), its length in `*bytes` (when
 * `bytes` is not NULL). Each call is checked. */
static inline st_scene *build_f(const float *p, const float *n, size_t stride,
                                size_t vertex_count, const uint32_t *idx, size_t triangle_count,
                                uint32_t flags, uint32_t iterations, void **memory,
                                size_t *bytes) {
    st_scene *scene = NULL;
    size_t length = 0;
    CHECK(st_scene_required_bytes(vertex_count, triangle_count, flags, &length) == ST_OK);
    *memory = malloc(length);
    CHECK(st_scene_build(*memory, length, p, stride, n, stride, vertex_count, idx, triangle_count,
                         flags, iterations, &scene) == ST_OK);
    if (bytes != NULL) *bytes = length;
    return scene;
}

#endif
