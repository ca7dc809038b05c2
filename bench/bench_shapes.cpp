// Google Benchmark: is an analytic shape worth its equation? A torus (major radius 1, minor
// 0.3) met by its quartic through the shape layer (accel/shape_intersector.h) against the
// same torus tessellated into 64 x 32 and 256 x 128 quads (4,096 and 65,536 triangles) in
// foton's wide BVH, and a CSG nut (a sphere x box minus three cylinders) as the shape layer's
// costliest case; one thread, the same 65,536 primary rays (a pinhole camera at z = 4) and
// 65,536 incoherent rays (from random points within 1.5 of the centre in random directions),
// traced as batches through Intersector::intersect. Rays per second; each side counts its hits.
// Names: shapes/<set>/<geometry>.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>

#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"

using namespace foton;

namespace {

constexpr int kRays = 65536;
constexpr float kMajor = 1.f, kMinor = 0.3f;

TriangleMesh tessellated_torus(int around, int across) {
    TriangleMesh m;
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < across; ++j) {
            const float phi = 2.f * kPi * float(i) / float(around);
            const float theta = 2.f * kPi * float(j) / float(across);
            const float rho = kMajor + kMinor * std::cos(theta);
            m.positions.insert(m.positions.end(), {rho * std::cos(phi), rho * std::sin(phi),
                                                   kMinor * std::sin(theta)});
        }
    auto at = [&](int i, int j) { return uint32_t((i % around) * across + (j % across)); };
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < across; ++j)
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j),
                                               at(i + 1, j + 1), at(i, j + 1)});
    return m;
}

// geometry 0: analytic torus; 1, 2: tessellated 64 x 32, 256 x 128; 3: the CSG nut.
std::unique_ptr<Scene> make_scene(int geometry) {
    auto s = std::make_unique<Scene>();
    s->materials.push_back(Material{});
    if (geometry == 0) {
        ShapePrimitive t;
        t.type = ShapeType::Torus;
        t.radius = kMajor;
        t.minor_radius = kMinor;
        t.place(Affine{});
        s->add_shape(AnalyticShape(t), 0);
    } else if (geometry == 3) {
        AnalyticShape nut;
        ShapePrimitive ball, box, bar;
        ball.type = ShapeType::Sphere;
        ball.radius = 1.f;
        ball.place(Affine{});
        box.type = ShapeType::Box;
        box.half = {0.78f, 0.78f, 0.78f};
        box.place(Affine{});
        uint32_t node = nut.combine(CsgOp::Intersection, nut.leaf(ball), nut.leaf(box));
        for (const Vec3& axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
            bar.type = ShapeType::Cylinder;
            bar.radius = 0.45f;
            bar.height = 3.f;
            bar.capped = true;
            bar.to_world = bar.to_object = Affine{};
            // The canonical z axis turned onto `axis`, centred.
            const Affine turn = axis.z > 0.f   ? Affine{}
                                : axis.x > 0.f ? Affine::rotate({0, 1, 0}, 90.f)
                                               : Affine::rotate({1, 0, 0}, -90.f);
            bar.place(turn * Affine::translate({0, 0, -1.5f}));
            node = nut.combine(CsgOp::Difference, node, nut.leaf(bar));
        }
        nut.finish();
        s->add_shape(std::move(nut), 0);
    } else {
        s->add_mesh(geometry == 1 ? tessellated_torus(64, 32) : tessellated_torus(256, 128), 0,
                    false);
    }
    return s;
}

struct Rays {
    RayBatch primary, incoherent;
    Rays() {
        std::mt19937 r(39);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (int i = 0; i < kRays; ++i) {
            const float sx = ((float(i % 256) + 0.5f) / 256.f) * 2.f - 1.f;
            const float sy = ((float(i / 256) + 0.5f) / 256.f) * 2.f - 1.f;
            primary.push({0.f, 0.f, 4.f}, normalize(Vec3{0.35f * sx, 0.35f * sy, -1.f}), 0.f,
                         kInfinity, uint32_t(i));
            const float ct = 2.f * u(r) - 1.f, st = std::sqrt(1.f - ct * ct), ph = 6.283f * u(r);
            const Vec3 o{3.f * u(r) - 1.5f, 3.f * u(r) - 1.5f, 3.f * u(r) - 1.5f};
            incoherent.push(o, {st * std::cos(ph), st * std::sin(ph), ct}, 0.f, kInfinity,
                            uint32_t(i));
        }
    }
};

const Rays& rays() {
    static const Rays r;
    return r;
}

void BM_shapes(benchmark::State& state) {
    const int geometry = int(state.range(0));
    const RayBatch& batch = state.range(1) == 0 ? rays().primary : rays().incoherent;
    const std::unique_ptr<Scene> scene = make_scene(geometry);
    const auto accel = make_intersector(*scene, AccelType::Bvh, 1);
    HitBatch hits;
    TraceCounters c;
    std::size_t hit_count = 0;
    for (auto _ : state) {
        accel->intersect(batch, hits, c);
        hit_count = 0;
        for (std::size_t i = 0; i < batch.size(); ++i) hit_count += hits.geom[i] != kNoHit;
        benchmark::DoNotOptimize(hit_count);
    }
    state.counters["hit_fraction"] = double(hit_count) / double(batch.size());
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(batch.size()));
}

void register_all() {
    const char* sets[] = {"primary", "incoherent"};
    const char* geometry[] = {"torus_analytic", "torus_mesh_4k", "torus_mesh_65k", "csg_nut"};
    for (int set = 0; set < 2; ++set)
        for (int g = 0; g < 4; ++g)
            benchmark::RegisterBenchmark(
                (std::string("shapes/") + sets[set] + "/" + geometry[g]).c_str(), BM_shapes)
                ->Args({g, set})
                ->Unit(benchmark::kMillisecond);
}

const int registered = (register_all(), 0);

}  // namespace
