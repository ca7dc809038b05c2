#include "serve.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "engine/film/aov.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/scene.h"
#include "engine/transport/registry/integrators.h"
#include "render_session.h"
#include "request_guard.h"
#include "scene_list.h"
#include "web_page.h"

namespace foton::app {

namespace fs = std::filesystem;

namespace {

// A whole field as a number of type T: no trailing text, not negative, not NaN, and within
// T's range (4294967297 is not a 32-bit width of 1).
template <typename T>
bool parse_number(const std::string& text, T& out) {
    try {
        std::size_t used = 0;
        if constexpr (std::is_floating_point_v<T>) {
            const double v = std::stod(text, &used);
            if (used != text.size() || !(v >= 0.0) || v > double(std::numeric_limits<T>::max()))
                return false;
            out = T(v);
        } else {
            const long long v = std::stoll(text, &used);
            if (used != text.size() || v < 0 ||
                static_cast<unsigned long long>(v) >
                    static_cast<unsigned long long>(std::numeric_limits<T>::max()))
                return false;
            out = T(v);
        }
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace

int run_serve(const ServeArgs& args) {
    if (args.port < 0 || args.port > 65535)
        throw InputError("--port", 0,
                         std::to_string(args.port) + " is not a TCP port (0 to 65535)");
    if (!is_loopback_host(args.host)) {
        if (!args.allow_remote)
            throw InputError("--host", 0,
                             args.host +
                                 " lets other machines reach the server, and anyone who "
                                 "can may start renders: add --allow-remote to mean it");
        std::fprintf(stderr,
                     "foton serve: warning: listening on %s: anyone on that network can start "
                     "renders on this machine\n",
                     args.host.c_str());
    }
    const std::vector<std::string> dirs =
        args.scene_dirs.empty() ? std::vector<std::string>{"scenes"} : args.scene_dirs;
    const std::map<std::string, std::string> scenes = list_scenes(dirs);
    // Scenes read only under these: a request cannot open (or see quoted) any other file.
    std::vector<std::string> readable = dirs;
    readable.insert(readable.end(), args.allow_read.begin(), args.allow_read.end());
    std::error_code ec;
    if (args.scene_dirs.empty() && args.allow_read.empty() &&
        std::filesystem::is_directory("../shared", ec))
        readable.push_back("../shared");
    confine_inputs(readable);
    // References the page may compare with: the EXRs under the same folders, by name.
    std::vector<std::string> reference_dirs;
    for (const std::string& d : readable)
        if (fs::is_directory(d, ec)) reference_dirs.push_back(d);
    const std::map<std::string, std::string> references = list_files(reference_dirs, {".exr"});
    RenderSession session;
    httplib::Server server;
    server.set_payload_max_length(kMaxRequestBody);
    // Each connection holds a worker until its request arrives or the read times out: with
    // httplib's 8 workers and 5 s, 20 idle or half-open connections delayed the page's own
    // requests by 18 s. Many workers and a short read timeout keep it answering.
    server.new_task_queue = [] { return new httplib::ThreadPool(kServeWorkers); };
    server.set_read_timeout(kServeReadTimeoutSeconds, 0);
    server.set_keep_alive_timeout(kServeReadTimeoutSeconds);
    int port = args.port;  // the bound port, known before the first request
    // Every request passes the guard first (request_guard.h); refused ones get 403.
    server.set_pre_routing_handler([&](const httplib::Request& req, httplib::Response& res) {
        const RequestView view{req.method,
                               req.path,
                               req.get_header_value("Host"),
                               req.get_header_value("Origin"),
                               req.get_header_value("Sec-Fetch-Site"),
                               req.get_header_value(kRequestTokenHeader)};
        const std::string why = refuse_reason(view, args.host, port);
        if (why.empty()) return httplib::Server::HandlerResponse::Unhandled;
        res.status = 403;
        res.set_content(nlohmann::json{{"error", std::string("refused: ") + why}}.dump(
                            -1, ' ', false, nlohmann::json::error_handler_t::replace),
                        "application/json");
        return httplib::Server::HandlerResponse::Handled;
    });
    server.set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
        res.set_header("X-Content-Type-Options", "nosniff");
        res.set_header("X-Frame-Options", "DENY");
    });

    server.Get("/", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(kWebPage, "text/html; charset=utf-8");
    });
    server.Get("/api/options", [&](const httplib::Request&, httplib::Response& res) {
        nlohmann::ordered_json out = {
            {"scenes", nlohmann::ordered_json::array()},
            {"integrators", nlohmann::ordered_json::array()},
            {"accelerators", {"bvh", "embree", "grid", "octree", "kdtree", "brute-simd", "brute"}}};
        for (const auto& [name, path] : scenes) out["scenes"].push_back(name);
        for (const IntegratorInfo& i : integrators()) out["integrators"].push_back(i.name);
        out["references"] = nlohmann::ordered_json::array();
        for (const auto& [name, path] : references) out["references"].push_back(name);
        out["aovs"] = nlohmann::ordered_json::array();
        for (const auto& [name, bit] : aov_names().entries) out["aovs"].push_back(name);
        res.set_content(out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                        "application/json");
    });
    server.Post("/api/render", [&](const httplib::Request& req, httplib::Response& res) {
        auto fail = [&](const std::string& message) {
            res.status = 400;
            res.set_content(nlohmann::json{{"error", message}}.dump(
                                -1, ' ', false, nlohmann::json::error_handler_t::replace),
                            "application/json");
        };
        const auto scene = scenes.find(req.get_param_value("scene"));
        if (scene == scenes.end())
            return fail("unknown scene '" + req.get_param_value("scene") + "'");
        SessionRequest r;
        r.scene_path = scene->second;
        r.integrator = req.get_param_value("integrator");
        r.accel = req.get_param_value("accel");
        if (const std::string ref = req.get_param_value("reference"); !ref.empty()) {
            const auto found = references.find(ref);
            if (found == references.end()) return fail("unknown reference '" + ref + "'");
            r.reference_path = found->second;
        }
        if (const std::string v = req.get_param_value("exclude_above"); !v.empty()) {
            float limit = 0.f;
            if (!parse_number(v, limit)) return fail("bad exclude_above '" + v + "'");
            r.exclude_above = limit;
        }
        if (const std::string v = req.get_param_value("aov"); !v.empty()) r.set["aov"] = v;
        const std::pair<const char*, std::function<bool(const std::string&)>> numbers[] = {
            {"threads", [&](const std::string& v) { return parse_number(v, r.threads); }},
            {"width", [&](const std::string& v) { return parse_number(v, r.width); }},
            {"height", [&](const std::string& v) { return parse_number(v, r.height); }},
            {"spp", [&](const std::string& v) { return parse_number(v, r.spp) && r.spp > 0; }},
            {"passes", [&](const std::string& v) { return parse_number(v, r.passes); }},
            {"time", [&](const std::string& v) { return parse_number(v, r.time); }},
            {"seed", [&](const std::string& v) { return parse_number(v, r.seed); }},
        };
        for (const auto& [key, parse] : numbers)
            if (req.has_param(key) && !req.get_param_value(key).empty() &&
                !parse(req.get_param_value(key)))
                return fail(std::string("bad ") + key + " '" + req.get_param_value(key) + "'");
        // The command line's limits, checked before anything starts (the job checks them
        // again with the scene's own resolution filled in).
        if (r.width > kMaxImageSide || r.height > kMaxImageSide ||
            uint64_t(r.width) * uint64_t(r.height) > kMaxImagePixels)
            return fail("width x height: at most " + std::to_string(kMaxImageSide) +
                        " per side and " + std::to_string(kMaxImagePixels) + " pixels");
        if (r.threads > kMaxThreads) return fail("threads: at most " + std::to_string(kMaxThreads));
        if (r.spp > kMaxSamplesPerPass)
            return fail(std::string("spp: at most ") + std::to_string(kMaxSamplesPerPass) +
                        " per pass");
        if (r.passes > kMaxPasses)
            return fail(std::string("passes: at most ") + std::to_string(kMaxPasses));
        // Further settings, one key=value per line.
        std::string set = req.get_param_value("set");
        for (std::size_t at = 0; at < set.size();) {
            std::size_t end = set.find('\n', at);
            if (end == std::string::npos) end = set.size();
            std::string line = set.substr(at, end - at);
            at = end + 1;
            line.erase(std::remove(line.begin(), line.end(), '\r'), line.end());
            if (line.find_first_not_of(" \t") == std::string::npos) continue;
            const auto eq = line.find('=');
            if (eq == std::string::npos || eq == 0)
                return fail("settings: expected key=value, got '" + line + "'");
            r.set[line.substr(0, eq)] = line.substr(eq + 1);
        }
        std::string error;
        if (!session.start(r, error)) {
            res.status = 409;
            res.set_content(nlohmann::json{{"error", error}}.dump(
                                -1, ' ', false, nlohmann::json::error_handler_t::replace),
                            "application/json");
            return;
        }
        res.set_content("{\"started\": true}", "application/json");
    });
    server.Post("/api/stop", [&](const httplib::Request&, httplib::Response& res) {
        session.stop();
        res.set_content("{\"stopping\": true}", "application/json");
    });
    server.Get("/api/status", [&](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        res.set_content(session.status_json(), "application/json");
    });
    // Images are shared snapshots streamed without a copy per request (render_session.h).
    auto send = [](httplib::Response& res, std::shared_ptr<const std::string> bytes,
                   const char* type) {
        const std::size_t size = bytes->size();
        res.set_content_provider(
            size, type, [bytes](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                return sink.write(bytes->data() + offset, std::min(length, bytes->size() - offset));
            });
    };
    server.Get("/api/image.png", [&](const httplib::Request& req, httplib::Response& res) {
        float stops = 0.f;
        if (req.has_param("stops")) {
            try {
                stops = std::stof(req.get_param_value("stops"));
            } catch (const std::exception&) {
                stops = 0.f;
            }
        }
        if (!std::isfinite(stops)) stops = 0.f;
        std::shared_ptr<const std::string> png = session.png(std::clamp(stops, -20.f, 20.f));
        if (!png) {
            res.status = 404;
            return;
        }
        res.set_header("Cache-Control", "no-store");
        if (req.has_param("download"))
            res.set_header("Content-Disposition", "attachment; filename=\"foton.png\"");
        send(res, std::move(png), "image/png");
    });
    // Raw float32 pixels for the page's viewer (pixel values, exposure, error views): the
    // image so far or an AOV (?layer=), or a listed reference (?reference=) fitted to
    // ?width= x ?height= as --reference fits one. Sizes and channels go in headers.
    auto send_pixels = [&](httplib::Response& res, std::shared_ptr<const PixelData> px) {
        std::string channels;
        for (const std::string& c : px->channels) channels += (channels.empty() ? "" : ",") + c;
        res.set_header("Cache-Control", "no-store");
        res.set_header("X-Width", std::to_string(px->width));
        res.set_header("X-Height", std::to_string(px->height));
        res.set_header("X-Channels", channels);
        auto bytes = std::shared_ptr<const std::string>(px, &px->bytes);
        send(res, std::move(bytes), "application/octet-stream");
    };
    server.Get("/api/pixels", [&](const httplib::Request& req, httplib::Response& res) {
        std::shared_ptr<const PixelData> px = session.pixels(req.get_param_value("layer"));
        if (!px) {
            res.status = 404;
            return;
        }
        send_pixels(res, std::move(px));
    });
    server.Get("/api/reference", [&](const httplib::Request& req, httplib::Response& res) {
        auto fail = [&](int status, const std::string& message) {
            res.status = status;
            res.set_content(nlohmann::json{{"error", message}}.dump(
                                -1, ' ', false, nlohmann::json::error_handler_t::replace),
                            "application/json");
        };
        const auto found = references.find(req.get_param_value("name"));
        if (found == references.end()) return fail(404, "unknown reference");
        int width = 0, height = 0;
        if (!parse_number(req.get_param_value("width"), width) ||
            !parse_number(req.get_param_value("height"), height) || width < 1 || height < 1 ||
            width > kMaxImageSide || height > kMaxImageSide)
            return fail(400, "width and height: the image's size");
        try {
            const Film ref = fit_reference(read_exr(found->second), width, height, found->first);
            auto px = std::make_shared<PixelData>();
            px->width = ref.width;
            px->height = ref.height;
            px->channels = {"R", "G", "B"};
            px->bytes.assign(reinterpret_cast<const char*>(ref.pixels.data()),
                             ref.pixels.size() * sizeof(RGB));
            send_pixels(res, std::move(px));
        } catch (const InputError& e) {
            fail(400, e.what());
        }
    });
    server.Get("/api/image.exr", [&](const httplib::Request&, httplib::Response& res) {
        std::shared_ptr<const std::string> exr = session.exr();
        if (!exr) {
            res.status = 404;
            return;
        }
        res.set_header("Content-Disposition", "attachment; filename=\"foton.exr\"");
        send(res, std::move(exr), "image/x-exr");
    });

    if (port == 0) {
        port = server.bind_to_any_port(args.host);
    } else if (!server.bind_to_port(args.host, port)) {
        port = -1;
    }
    if (port < 0)
        throw InputError("--port", 0,
                         "cannot listen on " + args.host + ":" + std::to_string(args.port));
    std::string reads;
    for (const std::string& f : input_confinement()) reads += (reads.empty() ? "" : ", ") + f;
    std::printf("foton serve: http://%s:%d/ (%zu scenes; reads files under %s; Ctrl-C stops)\n",
                args.host.c_str(), port, scenes.size(), reads.c_str());
    std::fflush(stdout);
    server.listen_after_bind();
    return 0;
}

}  // namespace foton::app
