/*
 * smoothtri_embree.h: smooth patches as an Embree 3 user geometry, beside the caller's own
 * triangles, curves and instances. Header-only: include it after <embree3/rtcore.h> is
 * available (it includes it) in C99 or C++, and link the smoothtri_capi library and embree3.
 *
 *     st_scene *patches = ...;                      // st_scene_build, see smoothtri.h
 *     RTCGeometry g = st_embree_new_geometry(device, patches);
 *     unsigned smooth_id = rtcAttachGeometry(rtc_scene, g);
 *     rtcReleaseGeometry(g);
 *     rtcCommitScene(rtc_scene);
 *     ...
 *     rtcIntersect1(rtc_scene, &context, &rayhit);  // primID = the input triangle
 *     if (rayhit.hit.geomID == smooth_id) {
 *         st_hit detail;                            // shading normal and t_error
 *         st_embree_hit_details(patches, &ray_as_cast, &rayhit.hit, &detail);
 *     }
 *
 * What the geometry reports, per hit: tfar = t, Ng = the smooth surface's unit normal
 * (oriented like the vertex normals), u, v = the barycentrics of the triangle's vertices 1
 * and 2, primID = the input triangle (not the patch), geomID and instID as Embree sets them.
 * Embree's hit has no room for the seamless shading normal and the certified t_error:
 * st_embree_hit_details recomputes them for one hit.
 *
 * The callbacks handle ray packets of any width N (rtcIntersect1/4/8/16, streams) lane by
 * lane with their valid masks, call the geometry's and the context's filter functions
 * (rtcFilterIntersection / rtcFilterOcclusion) for every candidate hit, and use the scene's
 * iterations N. Embree traces in float, so the plug-in takes float scenes (st_scene). The
 * st_scene must outlive the geometry; Embree may call the callbacks from any of its threads
 * (st_scene queries are thread-safe).
 *
 * Embree 4: include <embree4/rtcore.h>; the callbacks' context becomes RTCRayQueryContext
 * (instance ids move to args->context->instID as before), rtcFilterIntersection and
 * rtcFilterOcclusion become rtcInvokeIntersectFilterFromGeometry and
 * rtcInvokeOccludedFilterFromGeometry, the RTCFilterFunctionNArguments keep their fields, and
 * the valid mask and the SoA ray layout are unchanged. Only the two filter calls and the
 * include need editing; this header targets Embree 3.13 (Debian's libembree-dev), which CI
 * tests.
 *
 * SPDX-License-Identifier: MIT OR Apache-2.0
 */
#ifndef SMOOTHTRI_EMBREE_H
#define SMOOTHTRI_EMBREE_H

#include <embree3/rtcore.h>
#include <math.h>

#include "smoothtri.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Field k of lane i of Embree's N-wide SoA ray (rtcore_ray.h: org_x = 0, org_y, org_z,
 * tnear, dir_x, dir_y, dir_z, time, tfar = 8, mask, id, flags), and of its hit, which follows
 * the 12 ray fields (Ng_x = 0, Ng_y, Ng_z, u, v, primID = 5, geomID, instID[l] = 7 + l). */
#define ST_EMBREE_F(base, N, k, i) (((float *)(base))[(k) * (N) + (i)])
#define ST_EMBREE_U(base, N, k, i) (((unsigned int *)(base))[(k) * (N) + (i)])

/* Lane i of an N-wide ray as an st_ray. */
static inline st_ray st_embree__ray(const void *rays, unsigned int N, unsigned int i) {
    st_ray r;
    r.org_x = ST_EMBREE_F(rays, N, 0, i);
    r.org_y = ST_EMBREE_F(rays, N, 1, i);
    r.org_z = ST_EMBREE_F(rays, N, 2, i);
    r.tnear = ST_EMBREE_F(rays, N, 3, i);
    r.dir_x = ST_EMBREE_F(rays, N, 4, i);
    r.dir_y = ST_EMBREE_F(rays, N, 5, i);
    r.dir_z = ST_EMBREE_F(rays, N, 6, i);
    r.time = ST_EMBREE_F(rays, N, 7, i);
    r.tfar = ST_EMBREE_F(rays, N, 8, i);
    r.mask = ST_EMBREE_U(rays, N, 9, i);
    r.id = ST_EMBREE_U(rays, N, 10, i);
    r.flags = ST_EMBREE_U(rays, N, 11, i);
    return r;
}

/* The one-lane Embree ray and hit of a candidate, for the filter functions. */
static inline void st_embree__candidate(const st_rayhit *rh, unsigned int geom_id,
                                        const struct RTCIntersectContext *context,
                                        struct RTCRay *ray, struct RTCHit *hit) {
    unsigned int l;
    ray->org_x = rh->ray.org_x;
    ray->org_y = rh->ray.org_y;
    ray->org_z = rh->ray.org_z;
    ray->tnear = rh->ray.tnear;
    ray->dir_x = rh->ray.dir_x;
    ray->dir_y = rh->ray.dir_y;
    ray->dir_z = rh->ray.dir_z;
    ray->time = rh->ray.time;
    ray->tfar = rh->ray.tfar;
    ray->mask = rh->ray.mask;
    ray->id = rh->ray.id;
    ray->flags = rh->ray.flags;
    hit->Ng_x = rh->hit.ng_x;
    hit->Ng_y = rh->hit.ng_y;
    hit->Ng_z = rh->hit.ng_z;
    hit->u = rh->hit.u;
    hit->v = rh->hit.v;
    hit->primID = rh->hit.prim_id;
    hit->geomID = geom_id;
    for (l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; l++) hit->instID[l] = context->instID[l];
}

static inline void st_embree__bounds(const struct RTCBoundsFunctionArguments *args) {
    float b[6];
    struct RTCBounds *o = args->bounds_o;
    if (st_patch_bounds((const st_scene *)args->geometryUserPtr, args->primID, b) != ST_OK) {
        /* Not a patch of this scene (cannot happen: the count is the scene's): empty. */
        b[0] = b[1] = b[2] = INFINITY;
        b[3] = b[4] = b[5] = -INFINITY;
    }
    o->lower_x = b[0];
    o->lower_y = b[1];
    o->lower_z = b[2];
    o->upper_x = b[3];
    o->upper_y = b[4];
    o->upper_z = b[5];
}

/* One lane's candidate hit: the patch test's ray-hit, the one-lane Embree ray and hit, and
 * the filter functions' arguments over them (valid = accept: -1 until a filter refuses it). */
struct st_embree__lane {
    st_rayhit rh;
    struct RTCRay ray;
    struct RTCHit hit;
    struct RTCFilterFunctionNArguments filter;
    int accept;
};

/* Whether lane i of the N-wide `rays` is active (`valid`) and hits patch `prim` of the scene
 * `user`; if so, fills `c` for the filter functions. */
static inline bool st_embree__candidate_of(struct st_embree__lane *c, const int *valid,
                                           void *user, unsigned int prim, const void *rays,
                                           unsigned int N, unsigned int i, unsigned int geom_id,
                                           struct RTCIntersectContext *context) {
    if (valid[i] != -1) return false;
    c->rh.ray = st_embree__ray(rays, N, i);
    c->rh.hit.prim_id = ST_INVALID_ID;
    if (!st_patch_intersect((const st_scene *)user, prim, &c->rh)) return false;
    st_embree__candidate(&c->rh, geom_id, context, &c->ray, &c->hit);
    c->accept = -1;
    c->filter.valid = &c->accept;
    c->filter.geometryUserPtr = user;
    c->filter.context = context;
    c->filter.ray = (struct RTCRayN *)&c->ray;
    c->filter.hit = (struct RTCHitN *)&c->hit;
    c->filter.N = 1;
    return true;
}

/* st_embree__candidate_of for lane i of `rays`, from the callback arguments `args` (those of
 * the intersect and occluded callbacks share these fields). */
#define ST_EMBREE_CANDIDATE(c, args, rays, i)                                                  \
    st_embree__candidate_of((c), (args)->valid, (args)->geometryUserPtr, (args)->primID,       \
                            (rays), (args)->N, (i), (args)->geomID, (args)->context)

static inline void st_embree__intersect(const struct RTCIntersectFunctionNArguments *args) {
    unsigned int N = args->N, i, l;
    void *rays = args->rayhit;
    float *hits = (float *)args->rayhit + 12 * N;
    for (i = 0; i < N; i++) {
        struct st_embree__lane c;
        if (!ST_EMBREE_CANDIDATE(&c, args, rays, i)) continue;
        rtcFilterIntersection(args, &c.filter);
        if (c.accept != -1) continue;
        ST_EMBREE_F(rays, N, 8, i) = c.rh.ray.tfar;
        ST_EMBREE_F(hits, N, 0, i) = c.hit.Ng_x;
        ST_EMBREE_F(hits, N, 1, i) = c.hit.Ng_y;
        ST_EMBREE_F(hits, N, 2, i) = c.hit.Ng_z;
        ST_EMBREE_F(hits, N, 3, i) = c.hit.u;
        ST_EMBREE_F(hits, N, 4, i) = c.hit.v;
        ST_EMBREE_U(hits, N, 5, i) = c.hit.primID;
        ST_EMBREE_U(hits, N, 6, i) = c.hit.geomID;
        for (l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; l++)
            ST_EMBREE_U(hits, N, 7 + l, i) = c.hit.instID[l];
    }
}

static inline void st_embree__occluded(const struct RTCOccludedFunctionNArguments *args) {
    unsigned int N = args->N, i;
    for (i = 0; i < N; i++) {
        struct st_embree__lane c;
        if (!ST_EMBREE_CANDIDATE(&c, args, args->ray, i)) continue;
        rtcFilterOcclusion(args, &c.filter);
        if (c.accept == -1) ST_EMBREE_F(args->ray, N, 8, i) = -INFINITY;
    }
}

/*
 * A committed Embree user geometry of the patches of `scene` (one primitive per patch, in
 * patch order; hits report the input triangle as primID). Attach it to an RTCScene, release
 * it, commit the scene. The caller may still add filter functions and recommit it.
 * Returns NULL when `device` or `scene` is NULL or `scene` is not a float scene.
 */
static inline RTCGeometry st_embree_new_geometry(RTCDevice device, const st_scene *scene) {
    st_scene_info info;
    RTCGeometry geometry;
    if (device == NULL || st_scene_get_info(scene, &info) != ST_OK) return NULL;
    geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    if (geometry == NULL) return NULL;
    rtcSetGeometryUserPrimitiveCount(geometry, (unsigned int)info.patch_count);
    rtcSetGeometryUserData(geometry, (void *)scene);
    rtcSetGeometryBoundsFunction(geometry, st_embree__bounds, NULL);
    rtcSetGeometryIntersectFunction(geometry, st_embree__intersect);
    rtcSetGeometryOccludedFunction(geometry, st_embree__occluded);
    rtcCommitGeometry(geometry);
    return geometry;
}

/*
 * The shading normal and certified t_error of a hit that Embree reported on this geometry
 * (hit->geomID its id): re-runs the patch test of hit->primID's patch for `ray_as_cast`, the
 * ray as it was before rtcIntersect (its original tnear and tfar), and writes the whole
 * st_hit to `out` (the same t, u, v and Ng as Embree's hit, bit for bit, unless a filter
 * function rejected a nearer crossing of the same patch). One patch test per call.
 * Returns false (and leaves `out`) when the hit is not one of this scene's.
 */
static inline bool st_embree_hit_details(const st_scene *scene, const struct RTCRay *ray_as_cast,
                                         const struct RTCHit *hit, st_hit *out) {
    uint32_t prim;
    st_rayhit rh;
    if (ray_as_cast == NULL || hit == NULL || out == NULL) return false;
    if (st_patch_of_triangle(scene, hit->primID, &prim) != ST_OK) return false;
    rh.ray.org_x = ray_as_cast->org_x;
    rh.ray.org_y = ray_as_cast->org_y;
    rh.ray.org_z = ray_as_cast->org_z;
    rh.ray.tnear = ray_as_cast->tnear;
    rh.ray.dir_x = ray_as_cast->dir_x;
    rh.ray.dir_y = ray_as_cast->dir_y;
    rh.ray.dir_z = ray_as_cast->dir_z;
    rh.ray.time = ray_as_cast->time;
    rh.ray.tfar = ray_as_cast->tfar;
    rh.ray.mask = ray_as_cast->mask;
    rh.ray.id = ray_as_cast->id;
    rh.ray.flags = ray_as_cast->flags;
    if (!st_patch_intersect(scene, prim, &rh)) return false;
    *out = rh.hit;
    return true;
}

#undef ST_EMBREE_F
#undef ST_EMBREE_U
#undef ST_EMBREE_CANDIDATE

#ifdef __cplusplus
}
#endif

#endif /* SMOOTHTRI_EMBREE_H */
