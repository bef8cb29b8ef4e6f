// What an Embree renderer does with smoothtri_embree.h: one RTCScene with a flat ground (two
// Embree triangles), the smooth torus through the plug-in, and an instance of a second scene
// holding the torus again. Every hit is checked against st_intersect1 (the same bits for the
// torus), the analytic ground plane, and rtcOccluded1; packets of eight (rtcIntersect8) equal
// single rays; a geometry filter function that refuses odd triangles is honoured; and
// st_embree_hit_details gives st_intersect1's shading normal and t_error.
#include "smoothtri_embree.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

static int failures = 0;

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);   \
            failures++;                                                                    \
        }                                                                                  \
    } while (0)

namespace {

const float GROUND_Z = -0.5f;
const float SHIFT_X = 3.0f;  // the instance's translation

struct Vertex {
    float p[3], n[3];
};

// The 8x8 torus (R = 1, r = 0.4) in the xy plane, with its exact normals.
void torus(std::vector<Vertex> &v, std::vector<uint32_t> &idx) {
    const unsigned nu = 8, nv = 8;
    const double pi = 3.14159265358979323846;
    for (unsigned i = 0; i < nu; i++)
        for (unsigned j = 0; j < nv; j++) {
            double u = 2 * pi * i / nu, w = 2 * pi * j / nv;
            Vertex x;
            x.n[0] = float(std::cos(w) * std::cos(u));
            x.n[1] = float(std::cos(w) * std::sin(u));
            x.n[2] = float(std::sin(w));
            x.p[0] = float((1 + 0.4 * std::cos(w)) * std::cos(u));
            x.p[1] = float((1 + 0.4 * std::cos(w)) * std::sin(u));
            x.p[2] = float(0.4 * std::sin(w));
            v.push_back(x);
        }
    for (unsigned i = 0; i < nu; i++)
        for (unsigned j = 0; j < nv; j++) {
            uint32_t a = i * nv + j, b = ((i + 1) % nu) * nv + j;
            uint32_t c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
            uint32_t t[6] = {a, b, c, a, c, d};
            idx.insert(idx.end(), t, t + 6);
        }
}

RTCRayHit embree_ray(const st_ray &r) {
    RTCRayHit rh;
    std::memset(&rh, 0, sizeof rh);
    rh.ray.org_x = r.org_x;
    rh.ray.org_y = r.org_y;
    rh.ray.org_z = r.org_z;
    rh.ray.dir_x = r.dir_x;
    rh.ray.dir_y = r.dir_y;
    rh.ray.dir_z = r.dir_z;
    rh.ray.tnear = r.tnear;
    rh.ray.tfar = r.tfar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

// Rays from above the torus, tilted, over [-2.5, 2.5] x [-1.5, 1.5] (the instance at x = 3 is
// reached by some).
std::vector<st_ray> rays() {
    std::vector<st_ray> out;
    for (int i = 0; i < 48; i++)
        for (int j = 0; j < 24; j++) {
            st_ray r;
            std::memset(&r, 0, sizeof r);
            r.org_x = -2.5f + 6.5f * (i + 0.5f) / 48;
            r.org_y = -1.5f + 3.0f * (j + 0.5f) / 24;
            r.org_z = 3.0f;
            r.dir_x = 0.15f * std::sin(0.7f * i + 0.3f * j);
            r.dir_y = 0.1f * std::cos(0.4f * i);
            r.dir_z = -1.0f;
            r.tnear = 0.0f;
            r.tfar = INFINITY;
            r.mask = 0xffffffffu;
            out.push_back(r);
        }
    return out;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// u, v within 1e-5 and the normal (geometric, or shading with `shading`) within 1e-5 of
// `hit`'s.
bool close_hit(float u, float v, float nx, float ny, float nz, const st_hit &hit,
               bool shading = false) {
    float hx = shading ? hit.ns_x : hit.ng_x, hy = shading ? hit.ns_y : hit.ng_y;
    float hz = shading ? hit.ns_z : hit.ng_z;
    return std::fabs(u - hit.u) <= 1e-5f && std::fabs(v - hit.v) <= 1e-5f &&
           nx * hx + ny * hy + nz * hz >= 1 - 1e-5f;
}

// The geometry filter: refuses hits on odd input triangles.
void refuse_odd(const RTCFilterFunctionNArguments *args) {
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1) continue;
        if (RTCHitN_primID(args->hit, args->N, i) % 2 == 1) args->valid[i] = 0;
    }
}

}  // namespace

int main() {
    std::vector<Vertex> vb;
    std::vector<uint32_t> ib;
    torus(vb, ib);
    size_t bytes = 0;
    CHECK(st_scene_required_bytes(vb.size(), ib.size() / 3, ST_BUILD_SEAMS, &bytes) == ST_OK);
    std::vector<unsigned char> memory(bytes);
    st_scene *patches = nullptr;
    CHECK(st_scene_build(memory.data(), bytes, vb[0].p, sizeof(Vertex), vb[0].n, sizeof(Vertex),
                         vb.size(), ib.data(), ib.size() / 3, ST_BUILD_SEAMS, 8,
                         &patches) == ST_OK);
    if (!patches) return 1;

    RTCDevice device = rtcNewDevice("threads=1");
    CHECK(device != nullptr);
    RTCScene scene = rtcNewScene(device);

    // The flat ground: two Embree triangles.
    RTCGeometry ground = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *gv = static_cast<float *>(rtcSetNewGeometryBuffer(
        ground, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
    unsigned *gi = static_cast<unsigned *>(rtcSetNewGeometryBuffer(
        ground, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2));
    const float corners[12] = {-10, -10, GROUND_Z, 10, -10, GROUND_Z,
                               10,  10,  GROUND_Z, -10, 10, GROUND_Z};
    const unsigned quads[6] = {0, 1, 2, 0, 2, 3};
    std::memcpy(gv, corners, sizeof corners);
    std::memcpy(gi, quads, sizeof quads);
    rtcCommitGeometry(ground);
    unsigned ground_id = rtcAttachGeometry(scene, ground);
    rtcReleaseGeometry(ground);

    // The smooth torus through the plug-in.
    RTCGeometry smooth = st_embree_new_geometry(device, patches);
    CHECK(smooth != nullptr);
    CHECK(st_embree_new_geometry(device, nullptr) == nullptr);
    unsigned torus_id = rtcAttachGeometry(scene, smooth);

    // An instance of a second scene holding the torus again, moved by SHIFT_X.
    RTCScene inner = rtcNewScene(device);
    RTCGeometry smooth2 = st_embree_new_geometry(device, patches);
    rtcAttachGeometry(inner, smooth2);
    rtcReleaseGeometry(smooth2);
    rtcCommitScene(inner);
    RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, inner);
    const float xfm[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, SHIFT_X, 0, 0};  // column-major 3x4
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(inst);
    unsigned inst_id = rtcAttachGeometry(scene, inst);
    rtcReleaseGeometry(inst);
    rtcCommitScene(scene);
    CHECK(rtcGetDeviceError(device) == RTC_ERROR_NONE);

    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::vector<st_ray> all = rays();
    std::vector<RTCRayHit> singles;
    unsigned torus_hits = 0, ground_hits = 0, instance_hits = 0, exact = 0;
    for (const st_ray &r : all) {
        RTCRayHit rh = embree_ray(r);
        rtcIntersect1(scene, &context, &rh);
        singles.push_back(rh);
        st_rayhit own;
        std::memset(&own, 0, sizeof own);
        own.ray = r;
        st_intersect1(patches, &own);
        st_rayhit moved;
        std::memset(&moved, 0, sizeof moved);
        moved.ray = r;
        moved.ray.org_x = r.org_x - SHIFT_X;
        st_intersect1(patches, &moved);
        float t_ground = (GROUND_Z - r.org_z) / r.dir_z;
        bool torus_first = own.hit.prim_id != ST_INVALID_ID &&
                           (moved.hit.prim_id == ST_INVALID_ID || own.ray.tfar <= moved.ray.tfar);
        if (torus_first) {
            // The plug-in's hit is st_intersect1's: the same triangle, t within t_error (the
            // kernel samples the part of the patch's shell inside the ray's [tnear, tfar], and
            // Embree's tfar when it tests the patch differs from our BVH's), u, v and the
            // normal to rounding.
            torus_hits++;
            CHECK(rh.hit.geomID == torus_id);
            CHECK(rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID);
            CHECK(rh.hit.primID == own.hit.prim_id);
            CHECK(std::fabs(rh.ray.tfar - own.ray.tfar) <= own.hit.t_error);
            CHECK(close_hit(rh.hit.u, rh.hit.v, rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z, own.hit));
            exact += same_bits(rh.ray.tfar, own.ray.tfar) && same_bits(rh.hit.u, own.hit.u);
            CHECK(own.ray.tfar < t_ground);
            st_hit details;
            std::memset(&details, 0, sizeof details);
            RTCRay cast = embree_ray(r).ray;
            CHECK(st_embree_hit_details(patches, &cast, &rh.hit, &details));
            CHECK(details.prim_id == own.hit.prim_id && details.geom_id == 0);
            CHECK(close_hit(details.u, details.v, details.ns_x, details.ns_y, details.ns_z, own.hit,
                            true));
            CHECK(details.t_error > 0 && details.t_error <= 4 * own.hit.t_error + 1e-6f);
        } else if (moved.hit.prim_id != ST_INVALID_ID) {
            // Through the instance: the same patch, t within float rounding of the transform.
            instance_hits++;
            CHECK(rh.hit.geomID == 0 && rh.hit.instID[0] == inst_id);
            CHECK(rh.hit.primID == moved.hit.prim_id);
            CHECK(std::fabs(rh.ray.tfar - moved.ray.tfar) <= 1e-5f * moved.ray.tfar);
        } else {
            ground_hits++;
            CHECK(rh.hit.geomID == ground_id);
            CHECK(std::fabs(rh.ray.tfar - t_ground) <= 1e-5f * t_ground);
        }
        // Shadow rays: everything blocks (the ground spans every ray).
        RTCRay shadow = embree_ray(r).ray;
        rtcOccluded1(scene, &context, &shadow);
        CHECK(shadow.tfar == -INFINITY);
        // A shadow ray that stops short of everything is not blocked.
        shadow = embree_ray(r).ray;
        shadow.tfar = 1.0f;
        rtcOccluded1(scene, &context, &shadow);
        CHECK(shadow.tfar == 1.0f);
    }
    CHECK(torus_hits > 100 && ground_hits > 100 && instance_hits > 20);

    // Packets of eight: the same results as single rays (N = 8 callbacks; t to rounding, as
    // the packet traversal may test the patches in another order).
    for (size_t k = 0; k + 8 <= all.size(); k += 8) {
        alignas(32) RTCRayHit8 p;
        alignas(32) int valid[8];
        std::memset(&p, 0, sizeof p);
        for (unsigned l = 0; l < 8; l++) {
            const st_ray &r = all[k + l];
            valid[l] = -1;
            p.ray.org_x[l] = r.org_x;
            p.ray.org_y[l] = r.org_y;
            p.ray.org_z[l] = r.org_z;
            p.ray.dir_x[l] = r.dir_x;
            p.ray.dir_y[l] = r.dir_y;
            p.ray.dir_z[l] = r.dir_z;
            p.ray.tnear[l] = 0.0f;
            p.ray.tfar[l] = INFINITY;
            p.ray.mask[l] = 0xffffffffu;
            p.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
            p.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, scene, &context, &p);
        for (unsigned l = 0; l < 8; l++) {
            const RTCRayHit &one = singles[k + l];
            CHECK(p.hit.geomID[l] == one.hit.geomID && p.hit.primID[l] == one.hit.primID);
            if (one.hit.geomID == torus_id) {
                CHECK(std::fabs(p.ray.tfar[l] - one.ray.tfar) <= 1e-5f * one.ray.tfar);
                CHECK(std::fabs(p.hit.u[l] - one.hit.u) <= 1e-5f);
                CHECK(std::fabs(p.hit.v[l] - one.hit.v) <= 1e-5f);
            }
        }
    }

    // A filter function on the smooth geometry: odd triangles are refused, so the nearest
    // even triangle's hit (the user's loop over st_patch_intersect) or the ground wins.
    rtcSetGeometryIntersectFilterFunction(smooth, refuse_odd);
    rtcCommitGeometry(smooth);
    rtcCommitScene(scene);
    unsigned refused = 0;
    for (const st_ray &r : all) {
        if (r.org_x > 1.5f) continue;  // away from the instance, which has no filter
        RTCRayHit rh = embree_ray(r);
        rtcIntersect1(scene, &context, &rh);
        st_rayhit even;
        std::memset(&even, 0, sizeof even);
        even.ray = r;
        even.hit.prim_id = ST_INVALID_ID;
        st_scene_info info;
        st_scene_get_info(patches, &info);
        for (uint32_t prim = 0; prim < info.patch_count; prim++) {
            st_rayhit trial = even;
            if (st_patch_intersect(patches, prim, &trial) && trial.hit.prim_id % 2 == 0)
                even = trial;
        }
        if (even.hit.prim_id != ST_INVALID_ID) {
            CHECK(rh.hit.geomID == torus_id && rh.hit.primID == even.hit.prim_id);
            CHECK(std::fabs(rh.ray.tfar - even.ray.tfar) <= even.hit.t_error);
        } else {
            CHECK(rh.hit.geomID != torus_id);
        }
        st_rayhit any;
        std::memset(&any, 0, sizeof any);
        any.ray = r;
        st_intersect1(patches, &any);
        refused += any.hit.prim_id != ST_INVALID_ID && any.hit.prim_id % 2 == 1;
    }
    CHECK(refused > 20);
    rtcReleaseGeometry(smooth);
    rtcReleaseScene(scene);
    rtcReleaseScene(inner);
    CHECK(rtcGetDeviceError(device) == RTC_ERROR_NONE);
    rtcReleaseDevice(device);
    if (failures) {
        std::fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    std::printf("embree_test: %u torus (%u bit for bit as st_intersect1), %u instance, %u ground "
                "hits; all checks passed\n",
                torus_hits, exact, instance_hits, ground_hits);
    return 0;
}
