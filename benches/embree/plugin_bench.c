/*
 * The C side of the `embree` bench: one mesh and one set of rays (written by benches/embree.rs
 * to the file named by argv[1]) traced three ways in one process, one thread, interleaved
 * rounds, median of each:
 *   1. smoothtri's own BVH through the C API (st_intersect1, shading normal included);
 *   2. Embree's BVH over the smooth patches through the plug-in (smoothtri_embree.h);
 *   3. Embree's own triangles of the same mesh, Phong normal interpolated from u, v.
 * Prints one line per way: `row <name>|<Mrays/s>|<hits>`.
 *
 * File: u32 vertex_count, triangle_count, ray_count, rounds, iterations; then float positions
 * [3V], normals [3V], u32 indices [3T], float rays [6R] (origin, direction).
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include "smoothtri_embree.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void read_or_die(void *dst, size_t size, size_t count, FILE *f) {
    if (fread(dst, size, count, f) != count) {
        fprintf(stderr, "plugin_bench: short input file\n");
        exit(2);
    }
}

static volatile float sink;

int main(int argc, char **argv) {
    uint32_t head[5];
    FILE *f;
    float *pos, *nrm, *rays, *gv;
    uint32_t *idx;
    unsigned *gi;
    size_t V, T, R, rounds, k, way, bytes = 0;
    double *secs[3];
    unsigned hits[3] = {0, 0, 0};
    void *memory;
    st_scene *scene = NULL;
    RTCDevice device;
    RTCScene plug, flat;
    RTCGeometry g;
    struct RTCIntersectContext context;
    const char *names[3] = {"smoothtri BVH, st_intersect1 (C API)",
                            "Embree BVH + smoothtri plug-in, rtcIntersect1",
                            "Embree flat triangles of the same mesh, Phong normals, rtcIntersect1"};
    if (argc < 2 || !(f = fopen(argv[1], "rb"))) {
        fprintf(stderr, "usage: plugin_bench FILE\n");
        return 2;
    }
    read_or_die(head, 4, 5, f);
    V = head[0];
    T = head[1];
    R = head[2];
    rounds = head[3];
    pos = (float *)malloc(12 * V);
    nrm = (float *)malloc(12 * V);
    idx = (uint32_t *)malloc(12 * T);
    rays = (float *)malloc(24 * R);
    read_or_die(pos, 4, 3 * V, f);
    read_or_die(nrm, 4, 3 * V, f);
    read_or_die(idx, 4, 3 * T, f);
    read_or_die(rays, 4, 6 * R, f);
    fclose(f);

    if (st_scene_required_bytes(V, T, 0, &bytes) != ST_OK) return 3;
    memory = malloc(bytes);
    if (st_scene_build(memory, bytes, pos, 0, nrm, 0, V, idx, T, 0, head[4], &scene) != ST_OK)
        return 3;

    device = rtcNewDevice("threads=1");
    plug = rtcNewScene(device);
    g = st_embree_new_geometry(device, scene);
    rtcAttachGeometry(plug, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(plug);
    flat = rtcNewScene(device);
    g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    gv = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, V);
    gi = (unsigned *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, T);
    memcpy(gv, pos, 12 * V);
    memcpy(gi, idx, 12 * T);
    rtcCommitGeometry(g);
    rtcAttachGeometry(flat, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(flat);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) return 4;
    rtcInitIntersectContext(&context);

    for (way = 0; way < 3; way++) secs[way] = (double *)calloc(rounds, sizeof(double));
    /* Round 0 warms up; then the three ways in turn, each round. */
    for (k = 0; k <= rounds; k++) {
        for (way = 0; way < 3; way++) {
            size_t r;
            unsigned h = 0;
            double t0 = now();
            for (r = 0; r < R; r++) {
                const float *x = &rays[6 * r];
                if (way == 0) {
                    st_rayhit rh;
                    rh.ray.org_x = x[0]; rh.ray.org_y = x[1]; rh.ray.org_z = x[2];
                    rh.ray.dir_x = x[3]; rh.ray.dir_y = x[4]; rh.ray.dir_z = x[5];
                    rh.ray.tnear = 0.0f; rh.ray.tfar = INFINITY;
                    st_intersect1(scene, &rh);
                    if (rh.hit.prim_id != ST_INVALID_ID) {
                        h++;
                        sink = rh.hit.ns_x;
                    }
                } else {
                    struct RTCRayHit rh;
                    rh.ray.org_x = x[0]; rh.ray.org_y = x[1]; rh.ray.org_z = x[2];
                    rh.ray.dir_x = x[3]; rh.ray.dir_y = x[4]; rh.ray.dir_z = x[5];
                    rh.ray.tnear = 0.0f; rh.ray.tfar = INFINITY;
                    rh.ray.mask = 0xffffffffu; rh.ray.flags = 0; rh.ray.time = 0;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(way == 1 ? plug : flat, &context, &rh);
                    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                        h++;
                        if (way == 2) {
                            /* Phong: interpolate the vertex normals at u, v. */
                            const uint32_t *t = &idx[3 * rh.hit.primID];
                            float w = 1.0f - rh.hit.u - rh.hit.v, n[3];
                            int c;
                            for (c = 0; c < 3; c++)
                                n[c] = w * nrm[3 * t[0] + c] + rh.hit.u * nrm[3 * t[1] + c] +
                                       rh.hit.v * nrm[3 * t[2] + c];
                            sink = n[0] / sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                        } else {
                            sink = rh.hit.Ng_x;
                        }
                    }
                }
            }
            if (k > 0) secs[way][k - 1] = now() - t0;
            hits[way] = h;
        }
    }
    for (way = 0; way < 3; way++) {
        qsort(secs[way], rounds, sizeof(double), cmp_double);
        printf("row %s|%.3f|%u\n", names[way], (double)R / secs[way][rounds / 2] / 1e6, hits[way]);
        free(secs[way]);
    }
    rtcReleaseScene(plug);
    rtcReleaseScene(flat);
    rtcReleaseDevice(device);
    free(memory);
    free(pos); free(nrm); free(idx); free(rays);
    return 0;
}
