#include "vpm.h"

#include <any>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "beam_estimate.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/thread_clock.h"
#include "engine/core/thread_pinning.h"
#include "engine/core/warp.h"
#include "engine/film/pixel_owners.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/medium_locate.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/common/medium_tracking.h"
#include "engine/transport/common/next_event.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"
#include "grid_flights.h"
#include "volume_photons.h"

namespace foton {

namespace {

// A pass's camera paths of one image row, traced as one batch per bounce.
struct RowWork {
    RayBatch rays, next;
    HitBatch hits;
    MediumShadowRays shadow;
    std::vector<RGB> direct;  // per pixel of the row: what its shadow rays bring
    std::vector<SampleJob> jobs;
    std::vector<RGB> beta;
    std::vector<int32_t> medium;
    std::vector<uint32_t> depth, crossings, draws;
    GridFlights flights;  // a bounce's flights through grid media, as one batch
    std::vector<int32_t> flight_of;
    SegmentTransmittance segment;  // the beam estimate's transmittance along a segment
};

class VpmCamera {
  public:
    VpmCamera(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
              const LightSet& lights, const VpmSettings& own, uint64_t seed)
        : scene_(scene),
          settings_(settings),
          accel_(accel),
          lights_(lights),
          nee_(!own.direct_photons),
          seed_(seed) {}

    // The photons a pass's camera paths read: the maps, the volume photons as discs (the beam
    // estimate; null: the point estimate) and the radii.
    struct PassPhotons {
        const VolumePhotonMaps& maps;
        const PhotonDiscs* discs;
        float r_surface, r_volume;
    };

    // Pass `pass`'s estimate of every pixel of row y, added to sum[x].
    void trace_row(uint32_t pass, uint32_t y, const PassPhotons& photons, RGB* sum, RowWork& w,
                   RenderStats& stats) const {
        const float r_surface = photons.r_surface, r_volume = photons.r_volume;
        const uint32_t width = uint32_t(scene_.film.width);
        w.jobs.resize(width);
        for (uint32_t x = 0; x < width; ++x)
            w.jobs[x] = {
                x, y,    0,
                1, pass, scene_.film.pixel_id(x, y) + uint64_t(pass) * scene_.film.full_pixels()};
        w.rays.clear();
        generate_camera_rays(scene_, settings_.sampler, w.jobs, seed_, w.rays);
        stats.camera_rays += width;
        w.beta.assign(width, RGB{1.f});
        thread_local std::vector<float> weight;  // a filter with negative lobes
        if (camera_sample_weights(scene_, settings_.sampler, w.jobs, seed_, weight))
            for (uint32_t x = 0; x < width; ++x) w.beta[x] *= weight[x];
        w.medium.assign(width, scene_.camera_medium);
        w.depth.assign(width, 0);
        w.crossings.assign(width, 0);
        w.draws.assign(width, 0);
        w.shadow.clear();
        w.direct.assign(width, RGB{0.f});
        const float inv_area = 1.f / (kPi * r_surface * r_surface);
        const float inv_volume = 1.f / (4.f / 3.f * kPi * r_volume * r_volume * r_volume);
        while (!w.rays.empty()) {
            accel_.intersect(w.rays, w.hits, stats.trace);
            w.next.clear();
            auto number = [&](uint32_t slot) {
                return rng::uniform(seed_, kVolumeCameraStream, w.jobs[slot].id, w.draws[slot]++);
            };
            w.flights.track_batch(scene_, w.rays, w.hits, w.medium, w.beta, true, w.flight_of,
                                  number);
            for (std::size_t r = 0; r < w.rays.size(); ++r) {
                const uint32_t slot = w.rays.id[r];
                auto u = [&] { return number(slot); };
                sum[slot] += shade(r, slot, photons, inv_area, inv_volume, w, u);
            }
            std::swap(w.rays, w.next);
        }
        StageClock clock;
        w.shadow.resolve(scene_, accel_, TransmittanceEstimator::Exact, seed_, w.direct, stats,
                         clock);
        for (uint32_t x = 0; x < width; ++x) sum[x] += w.direct[x];
        stats.samples += width;
    }

  private:
    // One hit (or flight) of a row's path: what it adds to its pixel; continues it in w.next.
    template <class Uniform>
    RGB shade(std::size_t r, uint32_t slot, const PassPhotons& photons, float inv_area,
              float inv_volume, RowWork& w, Uniform&& u) const {
        const uint32_t geom = w.hits.geom[r];
        const Vec3 d = w.rays.direction(r);
        RGB& beta = w.beta[slot];
        const VolumePhotonMaps& maps = photons.maps;
        RGB in_medium{0.f};
        if (const int32_t mi = w.medium[slot]; mi != kNoMedium) {
            const Medium& med = scene_.media[std::size_t(mi)];
            const Vec3 o = w.rays.origin(r);
            if (photons.discs) {
                // The beam estimate over the whole segment; the direct light by a light sample
                // at a point a flight picks (what the flight weighs it by is T sigma_s / pdf).
                const float t_end = geom == kNoHit ? kInfinity : w.hits.t[r];
                if (nee_) {
                    const FreeFlight f = flight_of_entry(scene_, w.flights, w.flight_of, w.rays,
                                                         w.hits, r, mi, beta, u);
                    if (f.event == FreeFlight::Event::Scatter)
                        medium_direct(slot, o + d * f.t, -d, med, beta * f.weight, mi, w, u);
                }
                const BeamEstimate b = beam_estimate(*photons.discs, maps.volume, med, o, d, t_end,
                                                     nee_ ? kPhotonDirect : 0, w.segment, u);
                in_medium = beta * b.in;
                beta *= b.transmittance;
                if (beta.is_black()) return in_medium;
                return in_medium + surface(r, slot, photons, inv_area, w, u);
            }
            const FreeFlight f =
                flight_of_entry(scene_, w.flights, w.flight_of, w.rays, w.hits, r, mi, beta, u);
            if (f.event == FreeFlight::Event::Absorb) return RGB{0.f};
            if (f.event == FreeFlight::Event::Scatter) {
                // The flight's weight without sigma_s, which the photons' density carries.
                const Vec3 p = o + d * f.t;
                const RGB s = med.homogeneous() ? med.sigma_s : med.at(p).sigma_s;
                const RGB wt{s.r > 0.f ? f.weight.r / s.r : 0.f, s.g > 0.f ? f.weight.g / s.g : 0.f,
                             s.b > 0.f ? f.weight.b / s.b : 0.f};
                RGB in{0.f};
                maps.volume.for_each_in_radius(p, photons.r_volume, [&](uint32_t i, float) {
                    if (nee_ && (maps.volume.flags(i) & kPhotonDirect)) return;
                    in += maps.volume.power(i) *
                          henyey_greenstein(dot(-d, maps.volume.incident(i)), med.g);
                });
                if (nee_) medium_direct(slot, p, -d, med, beta * f.weight, mi, w, u);
                return beta * wt * in * inv_volume;
            }
            beta *= f.weight;
        }
        return surface(r, slot, photons, inv_area, w, u);
    }

    // The path's hit beyond any medium: emission, the surface estimate and direct light, the
    // delta lobes' continuation (or the sky, with nothing hit).
    template <class Uniform>
    RGB surface(std::size_t r, uint32_t slot, const PassPhotons& photons, float inv_area,
                RowWork& w, Uniform&& u) const {
        const uint32_t geom = w.hits.geom[r];
        const Vec3 d = w.rays.direction(r);
        RGB& beta = w.beta[slot];
        const VolumePhotonMaps& maps = photons.maps;
        const float r_surface = photons.r_surface;
        if (geom == kNoHit) return beta * scene_.background_along(w.rays.origin(r), d);
        const SurfacePoint sp = surface_at(scene_, w.rays, w.hits, r);
        std::optional<Material> scratch;
        const Material& m = scene_.material_at(geom, sp.tex(), scratch);
        if (m.is_interface) {
            if (++w.crossings[slot] > kMaxPathCrossings) return RGB{0.f};
            w.medium[slot] = medium_after(scene_, geom, sp, d, w.medium[slot]);
            w.next.push(offset_origin(sp, d), d, 0.f, kInfinity, slot);
            return RGB{0.f};
        }
        RGB add = m.emits_towards(sp.front_face) ? beta * m.emission : RGB{0.f};
        if (m.bsdf.empty()) return add;
        const warp::Frame frame = sp.frame();
        const Vec3 wo = frame.to_local(-d);
        const BsdfContext ctx{sp.front_face, Transport::Radiance};
        if (m.bsdf.has_non_delta()) {
            RGB in{0.f};
            maps.surface.for_each_in_radius(sp.p, r_surface, [&](uint32_t i, float) {
                if (nee_ && (maps.surface.flags(i) & kPhotonDirect)) return;
                const Vec3 wi = maps.surface.incident(i);
                if (!m.bsdf.side_allowed(wi, sp.ng)) return;
                in += m.bsdf.f(wo, frame.to_local(wi), ctx) * maps.surface.power(i);
            });
            add += beta * in * inv_area;
            if (nee_) {
                DirectSample ds;
                const ShadingPoint v(sp, m, d, beta, slot, 0, w.jobs[slot].id);
                // Drawn in a fixed order: function arguments are evaluated in any.
                const float u0 = u(), u1 = u(), u2 = u(), u3 = u();
                if (sample_direct(lights_, v, u0, {u1, u2}, u3, ds))
                    w.shadow.push(ds.origin, ds.dir, ds.tmax,
                                  medium_after(scene_, geom, sp, ds.dir, w.medium[slot]), slot,
                                  ds.value, w.jobs[slot].id);
            }
        }
        // The delta lobes go on (their share of the throughput in the sample's weight).
        if (!m.bsdf.has_delta() || ++w.depth[slot] > settings_.max_depth) return add;
        BsdfSample bs;
        const float u0 = u(), u1 = u(), u2 = u();
        if (!m.bsdf.sample(wo, u0, {u1, u2}, ctx, bs, kSpecular)) return add;
        const Vec3 wi = frame.to_world(bs.wi);
        const float side = dot(wi, sp.ng);
        if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) return add;
        beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
        if (beta.is_black()) return add;
        w.medium[slot] = medium_after(scene_, geom, sp, wi, w.medium[slot]);
        w.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
        return add;
    }

    // Next event estimation of the direct light scattered at p in medium `med` (index mi)
    // towards wo, for a path of throughput `weight` (sigma_s included): one light sample.
    template <class Uniform>
    void medium_direct(uint32_t slot, const Vec3& p, const Vec3& wo, const Medium& med,
                       const RGB& weight, int32_t mi, RowWork& w, Uniform&& u) const {
        LightPick pick;
        LightSample ls;
        if (!lights_.pick(u(), p, Vec3{}, pick)) return;
        const float u0 = u(), u1 = u(), u2 = u();  // in a fixed order (see surface())
        if (!lights_.sample_li(pick.light, p, {u0, u1}, u2, ls, pick.tri)) return;
        const RGB value =
            weight * ls.Li * (henyey_greenstein(dot(wo, ls.wi), med.g) / (pick.pmf * ls.pdf));
        if (value.is_black()) return;
        SurfacePoint at{};
        at.p = p;
        const ShadowRay r = shadow_ray_to(at, ls);
        w.shadow.push(r.origin, r.dir, r.tmax, mi, slot, value, w.jobs[slot].id);
    }

    const Scene& scene_;
    const RenderSettings& settings_;
    const Intersector& accel_;
    const LightSet& lights_;
    const bool nee_;
    uint64_t seed_;
};

}  // namespace

void parse_vpm(const ParamSet& params, RenderSettings& settings) {
    VpmSettings own;
    own.volume_radius = params.real("volume_radius", own.volume_radius, 0.f);
    const std::string direct = params.text("direct", "nee");
    if (direct != "nee" && direct != "photons")
        params.fail("direct", "direct is nee or photons, not '" + direct + "'");
    own.direct_photons = direct == "photons";
    const std::string estimator = params.text("estimator", "point");
    if (estimator != "point" && estimator != "beam")
        params.fail("estimator", "estimator is point or beam, not '" + estimator + "'");
    own.beam = estimator == "beam";
    settings.own = own;
}

RenderResult render_vpm(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& opt) {
    refuse_emitting_media(scene,
                          "vpm sends photons from lights only: render it with type=\"volpath\"");
    const LightSet lights(scene, settings.light_selection, settings.projection_maps);
    if (lights.empty()) throw InputError(scene.source, 0, "vpm needs a light");
    const PhotonSettings& ps = settings.photon;
    const VpmSettings* own = std::any_cast<VpmSettings>(&settings.own);
    const float scene_radius = 0.5f * length(scene.bounds().diagonal());
    float r_surface = ps.initial_radius > 0.f ? ps.initial_radius : 0.01f * scene_radius;
    float r_volume = own && own->volume_radius > 0.f ? own->volume_radius : 0.05f * scene_radius;
    const uint64_t per_pass =
        ps.photons_per_pass > 0 ? ps.photons_per_pass : scene.film.full_pixels();
    const int w = scene.film.width, h = scene.film.height;
    const std::size_t npix = std::size_t(w) * std::size_t(h);
    std::vector<RGB> sum(npix, RGB{0.f});
    const VolumePhotonTracer tracer(scene, accel, lights, opt.seed);
    const VpmCamera camera(scene, settings, accel, lights, own ? *own : VpmSettings{}, opt.seed);
    const int threads = resolve_threads(opt.threads);
    PinnedArena arena(threads);
    tbb::enumerable_thread_specific<RenderStats> local;
    tbb::enumerable_thread_specific<RowWork> rows;
    const Cluster& cluster = cluster_or_solo(opt.cluster);
    const PixelOwners owner = owners_by_row(w, h, cluster.size());
    const std::vector<uint64_t> my_rows = dealt_in_turn(uint64_t(h), cluster);
    auto image = [&](uint32_t passes) {
        Film f(w, h);
        const float inv = passes > 0 ? 1.f / float(passes) : 0.f;
        for (std::size_t i = 0; i < npix; ++i) f.pixels[i] = sum[i] * inv;
        gather_to_root(cluster, owner, f.pixels);
        return f;
    };
    RenderOptions pass_opt = opt;
    if (pass_opt.max_passes == 0 && !(opt.time_limit > 0.f))
        pass_opt.max_passes = std::max<uint32_t>(1, opt.spp);
    PassControl control(pass_opt);
    const ProgressTask task = control.task("vpm passes", 1);
    uint32_t pass = 0;
    VolumePhotonMaps maps;
    const bool beam = own && own->beam;
    PhotonDiscs discs;
    StageGraph graph;
    graph.set_progress(opt.progress);
    const uint32_t photons = graph.add("photons", [&]() -> uint64_t {
        maps = tracer.run(1000 + pass, per_pass, settings.max_depth, local.local(), opt.cluster,
                          opt.cancel);
        return per_pass;
    });
    const uint32_t balance = graph.add("balance", [&]() -> uint64_t {
        StageClock clock;
        maps.surface.build(timed_parallel_invoke(ThreadClock::for_chunks()));
        maps.volume.build(timed_parallel_invoke(ThreadClock::for_chunks()));
        if (beam)
            discs.build(maps.volume, r_volume, timed_parallel_invoke(ThreadClock::for_chunks()));
        const std::size_t n = maps.surface.size() + maps.volume.size();
        local.local().add_wall(Stage::Balance, n, clock);
        return n;
    });
    const uint32_t gather = graph.add("camera-paths", [&]() -> uint64_t {
        StageClock clock;
        BusyTime* const busy = ThreadClock::for_chunks();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, my_rows.size()),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              const ThreadClock clock(busy);
                              for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                  if (opt.cancel && opt.cancel->load(std::memory_order_relaxed))
                                      return;
                                  const uint32_t y = uint32_t(my_rows[i]);
                                  camera.trace_row(
                                      pass, y, {maps, beam ? &discs : nullptr, r_surface, r_volume},
                                      &sum[std::size_t(y) * std::size_t(w)], rows.local(),
                                      local.local());
                              }
                          });
        const std::size_t n = my_rows.size() * std::size_t(w);
        local.local().add_wall(Stage::Shade, n, clock);
        return n;
    });
    graph.edge(photons, balance);
    graph.edge(balance, gather);
    control.run(
        [&](uint32_t k) {
            pass = k;
            graph.run(arena);
            pass = k + 1;
            // Knaus & Zwicker's shrinking: area on surfaces, volume in media.
            const float ratio = (float(pass) + ps.alpha) / (float(pass) + 1.f);
            r_surface *= std::sqrt(ratio);
            // The beam estimate's kernel is a disc: its radius shrinks as a surface's does.
            r_volume *= beam ? std::sqrt(ratio) : std::cbrt(ratio);
            task.advance();
        },
        [&] { return image(pass); }, [&] { return double(pass); });
    RenderStats stats;
    for (const RenderStats& s : local) stats.merge(s);
    stats.wall_seconds = control.elapsed();
    stats.threads = threads;
    stats.passes = pass;
    RenderResult result;
    result.stats = stats;
    result.stats.graph = graph.report();
    result.film = image(pass);
    result.samples_per_pixel.assign(npix, pass);
    return result;
}

}  // namespace foton
