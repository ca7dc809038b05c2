// The uniform grid on the benchmark's own scenes and ray sets (bench/ray_sets.h): single-ray
// closest hit (with and without the mailbox) and any-hit equal brute force on every ray of the
// primary, diffuse and shadow sets, and coherent packet traversal equals single-ray traversal ray
// for ray.
#include <catch2/catch.hpp>
#include <numeric>

#include "bench/ray_sets.h"
#include "brute_oracle.h"
#include "kernels/uniform_grid.h"
#include "test_util.h"

using namespace foton;
using namespace foton::kern;

namespace {

UniformGrid grid_of(const TriangleMesh& m, bool mailbox = false) {
    UniformGrid g;
    GridParams gp;
    gp.mailbox = mailbox;
    g.build(m.positions.data(), m.indices.data(), m.num_triangles(), gp);
    return g;
}

// Traces `rays` as bundles of `per_bundle` W-wide packets and checks each ray against the
// single-ray grid: the same hit or miss and the same t (ids may differ only on exact ties).
std::size_t check_packets(const UniformGrid& g, const std::vector<Ray1>& rays,
                          std::size_t per_bundle) {
    constexpr std::size_t W = kBlockWidth;
    std::size_t hits = 0;
    for (std::size_t i = 0; i + per_bundle * W <= rays.size(); i += per_bundle * W) {
        RayPacket pk[kMaxGridPackets];
        PacketHits ph[kMaxGridPackets];
        for (std::size_t p = 0; p < per_bundle; ++p)
            for (std::size_t l = 0; l < W; ++l) {
                const Ray1& r = rays[i + p * W + l];
                pk[p].ox[l] = r.ox, pk[p].oy[l] = r.oy, pk[p].oz[l] = r.oz;
                pk[p].dx[l] = r.dx, pk[p].dy[l] = r.dy, pk[p].dz[l] = r.dz;
                pk[p].tmin[l] = r.tmin;
                ph[p].t[l] = r.tmax;
                ph[p].id[l] = kInvalidId;
            }
        g.intersect_packets(pk, per_bundle, ph);
        for (std::size_t p = 0; p < per_bundle; ++p)
            for (std::size_t l = 0; l < W; ++l) {
                TriHit h;
                const bool hit = g.intersect(rays[i + p * W + l], h);
                REQUIRE(hit == (ph[p].id[l] != kInvalidId));
                if (hit) {
                    REQUIRE(ph[p].t[l] == h.t);
                    ++hits;
                }
            }
    }
    return hits;
}

}  // namespace

TEST_CASE("grid equals brute force on every ray of the benchmark ray sets", "[kernel][grid]") {
    for (const char* name : {"bunny", "teapot", "cornell", "stadium", "dragon"}) {
        INFO(name);
        const bool big = std::string(name) == "dragon";
        const bench::KernelScene scene = bench::load_kernel_scene(name);
        const bench::RaySets sets = bench::make_ray_sets(scene, big ? 32 : 64, big ? 512 : 2048);
        const UniformGrid g = grid_of(scene.mesh);
        const UniformGrid gm = grid_of(scene.mesh, true);
        const test::BruteOracle brute(scene.mesh);
        std::size_t hits = 0;
        for (const auto* set : {&sets.primary, &sets.diffuse}) {
            for (std::size_t i = 0; i < set->size(); i += test::kSanitizedStride) {
                const Ray1& r = (*set)[i];
                TriHit hb, hg, hm;
                const bool b = brute.closest(r, hb);
                REQUIRE(g.intersect(r, hg) == b);
                REQUIRE(gm.intersect(r, hm) == b);
                if (b) {
                    REQUIRE(hg.t == hb.t);
                    REQUIRE(hm.t == hb.t);
                    ++hits;
                }
            }
        }
        std::size_t blocked = 0;
        for (std::size_t i = 0; i < sets.shadow.size(); i += test::kSanitizedStride) {
            const Ray1& r = sets.shadow[i];
            TriHit hb;
            const bool b = brute.closest(r, hb);
            REQUIRE(g.occluded(r) == b);
            blocked += b;
        }
        // The sets are not degenerate: a fair share of rays hit and of shadow rays are blocked.
        CHECK(hits > sets.primary.size() / 20 / test::kSanitizedStride);
        CHECK(blocked > 0);
    }
}

TEST_CASE("coherent packet traversal equals single-ray traversal", "[kernel][grid]") {
    for (const char* name : {"bunny", "cornell", "stadium"}) {
        INFO(name);
        const bench::KernelScene scene = bench::load_kernel_scene(name);
        const bench::RaySets sets = bench::make_ray_sets(scene, 256, 8192);
        const UniformGrid g = grid_of(scene.mesh);
        // Morton order: bundles of 1, 4 and 16 packets are square pixel blocks.
        for (std::size_t per : {std::size_t(1), std::size_t(4), kMaxGridPackets}) {
            INFO(per);
            CHECK(check_packets(g, sets.primary, per) > sets.primary.size() / 20);
            // Incoherent bundles: mixed direction signs take the single-ray fallback; the
            // shadow rays mostly share the sign towards the light but start far apart.
            check_packets(g, sets.diffuse, per);
            check_packets(g, sets.shadow, per);
        }
    }
}

TEST_CASE("packet traversal leaves inert lanes alone", "[kernel][grid]") {
    const bench::KernelScene scene = bench::load_kernel_scene("cornell");
    const bench::RaySets sets = bench::make_ray_sets(scene, 16, 0);
    const UniformGrid g = grid_of(scene.mesh);
    RayPacket pk;
    PacketHits ph;
    for (std::size_t l = 0; l < kBlockWidth; ++l) {
        const Ray1& r = sets.primary[l];
        pk.ox[l] = r.ox, pk.oy[l] = r.oy, pk.oz[l] = r.oz;
        pk.dx[l] = r.dx, pk.dy[l] = r.dy, pk.dz[l] = r.dz, pk.tmin[l] = 0.f;
        ph.t[l] = (l % 3 == 0) ? -kInf : kInf;  // every third lane unused
        ph.id[l] = kInvalidId;
    }
    g.intersect_packets(&pk, 1, &ph);
    for (std::size_t l = 0; l < kBlockWidth; ++l) {
        if (l % 3 == 0) {
            CHECK(ph.t[l] == -kInf);
            CHECK(ph.id[l] == kInvalidId);
        } else {
            CHECK(ph.id[l] != kInvalidId);  // every camera ray hits the closed box
        }
    }
}
