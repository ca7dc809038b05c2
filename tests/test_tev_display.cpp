// The live preview: a minimal TCP listener speaking tev's protocol receives what foton sends
// and decodes it back into images.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <thread>

#include "engine/app/tev_display.h"
#include "engine/film/image_io.h"
#include "test_util.h"

using namespace foton;

namespace {

// Accepts one connection on 127.0.0.1 and keeps every byte until the peer closes.
class TevListener {
  public:
    TevListener() {
        fd_ = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
        socklen_t len = sizeof a;
        getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
        REQUIRE(listen(fd_, 1) == 0);
        thread_ = std::thread([this] {
            const int c = accept(fd_, nullptr, nullptr);
            if (c < 0) return;
            char buf[65536];
            for (ssize_t n; (n = read(c, buf, sizeof buf)) > 0;) bytes_.append(buf, std::size_t(n));
            close(c);
        });
    }
    ~TevListener() {
        shutdown(fd_, SHUT_RDWR);
        if (thread_.joinable()) thread_.join();
        close(fd_);
    }
    std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
    // Waits for the peer to close, then returns everything it sent.
    const std::string& received() {
        thread_.join();
        return bytes_;
    }

  private:
    int fd_ = -1, port_ = 0;
    std::thread thread_;
    std::string bytes_;
};

// Reads tev's packets back, as tev does.
struct Reader {
    const std::string& s;
    std::size_t at = 0;
    template <typename T>
    T raw() {
        T v;
        REQUIRE(at + sizeof v <= s.size());
        std::memcpy(&v, s.data() + at, sizeof v);
        at += sizeof v;
        return v;
    }
    std::string str() {
        const std::size_t end = s.find('\0', at);
        REQUIRE(end != std::string::npos);
        std::string v = s.substr(at, end - at);
        at = end + 1;
        return v;
    }
};

struct Decoded {
    std::vector<std::string> closed;
    int width = 0, height = 0;
    std::vector<std::string> channels;
    std::vector<Film> images;  // the image after each update that completed its last row
    // Every other channel's values as last sent (width x height floats each).
    std::map<std::string, std::vector<float>> planes;
};

Decoded decode(const std::string& bytes, const std::string& name) {
    Decoded d;
    Reader r{bytes};
    Film canvas;
    while (r.at < bytes.size()) {
        const std::size_t start = r.at;
        const uint32_t size = r.raw<uint32_t>();
        REQUIRE(start + size <= bytes.size());
        const uint8_t type = r.raw<uint8_t>();
        if (type == 2) {
            d.closed.push_back(r.str());
        } else if (type == 4) {
            CHECK(r.raw<uint8_t>() == 1);  // grab focus
            CHECK(r.str() == name);
            d.width = r.raw<int32_t>();
            d.height = r.raw<int32_t>();
            const int32_t n = r.raw<int32_t>();
            d.channels.clear();  // made again: the new list
            for (int32_t c = 0; c < n; ++c) d.channels.push_back(r.str());
            canvas = Film(d.width, d.height);
        } else {
            REQUIRE(type == 6);
            r.raw<uint8_t>();
            CHECK(r.str() == name);
            const int32_t n = r.raw<int32_t>();
            REQUIRE(n >= 1);
            std::vector<std::string> ch;
            for (int32_t c = 0; c < n; ++c) ch.push_back(r.str());
            for (const std::string& c : ch)
                CHECK(std::find(d.channels.begin(), d.channels.end(), c) != d.channels.end());
            const int32_t x = r.raw<int32_t>(), y = r.raw<int32_t>();
            const int32_t w = r.raw<int32_t>(), h = r.raw<int32_t>();
            std::vector<int64_t> offset(static_cast<std::size_t>(n)), stride(offset);
            for (int64_t& o : offset) o = r.raw<int64_t>();
            for (int64_t& s : stride) s = r.raw<int64_t>();
            std::vector<float> data((start + size - r.at) / sizeof(float));
            std::memcpy(data.data(), bytes.data() + r.at, data.size() * sizeof(float));
            r.at = start + size;
            REQUIRE((x >= 0 && y >= 0 && x + w <= d.width && y + h <= d.height));
            if (ch != std::vector<std::string>{"R", "G", "B"}) {
                for (int32_t c = 0; c < n; ++c) {
                    std::vector<float>& plane = d.planes[ch[std::size_t(c)]];
                    plane.resize(std::size_t(d.width) * std::size_t(d.height));
                    for (int64_t p = 0; p < int64_t(w) * h; ++p) {
                        const std::size_t i =
                            std::size_t(offset[std::size_t(c)] + p * stride[std::size_t(c)]);
                        if (i >= data.size()) FAIL("update's data too short");
                        plane[std::size_t(y + p / w) * std::size_t(d.width) +
                              std::size_t(x + p % w)] = data[i];
                    }
                }
                continue;
            }
            for (int64_t p = 0; p < int64_t(w) * h; ++p) {
                float* px = &canvas.at(x + int(p % w), y + int(p / w)).r;
                for (int c = 0; c < 3; ++c) {
                    const std::size_t i =
                        std::size_t(offset[std::size_t(c)] + p * stride[std::size_t(c)]);
                    if (i >= data.size()) FAIL("update's data too short");
                    px[c] = data[i];
                }
            }
            if (y + h == d.height) d.images.push_back(canvas);
        }
        REQUIRE(r.at == start + size);
    }
    return d;
}

bool same(const Film& a, const Film& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(RGB)) == 0;
}

Film pattern(int w, int h, float k) {
    Film f(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) f.at(x, y) = RGB(k * x, k * y + 0.5f, k * (x ^ y) - 1.f);
    return f;
}

}  // namespace

TEST_CASE("tev display: every image shown reaches the viewer and decodes exactly", "[tev]") {
    // 600 x 500 is sent in two bands of rows.
    for (const auto& [w, h] : {std::pair{24, 16}, std::pair{600, 500}}) {
        TevListener tev;
        std::vector<Film> shown;
        {
            app::TevDisplay display(tev.address(), "shown.exr", w, h);
            for (int k = 1; k <= 3; ++k) {
                shown.push_back(pattern(w, h, 0.25f * float(k)));
                display.show(shown.back());
                display.flush();
            }
            CHECK(display.sent() == 3);
        }
        const Decoded d = decode(tev.received(), "shown.exr");
        CHECK(d.closed == std::vector<std::string>{"shown.exr"});
        CHECK(d.width == w);
        CHECK(d.height == h);
        CHECK(d.channels == std::vector<std::string>{"R", "G", "B"});
        REQUIRE(d.images.size() == 3);
        for (int k = 0; k < 3; ++k) CHECK(same(d.images[std::size_t(k)], shown[std::size_t(k)]));
    }
}

TEST_CASE("foton render --display: a progressive render streams its passes to tev", "[tev][cli]") {
    test::TempDir dir;
    const std::string scene = test::source_path("scenes/cornell-diffuse.xml");
    for (const char* integrator : {"path", "sppm", "light"}) {
        INFO(integrator);
        TevListener tev;
        const std::string cmd = std::string(FOTON_BINARY) + " render " + scene +
                                " --width 40 --height 30 --passes 4 -q --integrator " + integrator +
                                " --display " + tev.address() + " -o " + dir.file("live.exr");
        REQUIRE(std::system(cmd.c_str()) == 0);
        const Decoded d = decode(tev.received(), "live.exr");
        CHECK(d.width == 40);
        CHECK(d.height == 30);
        // Passes are sent as they end; one still being sent is replaced by a newer one, so
        // between 1 and 4 arrive, and the last is the image written.
        CHECK(d.images.size() >= 1);
        CHECK(d.images.size() <= 4);
        REQUIRE_FALSE(d.images.empty());
        CHECK(same(d.images.back(), read_exr(dir.file("live.exr"))));
    }
}

namespace {

// Renders `args` (scene file and flags, under the source tree) streaming to a listener and
// returns what tev received for the image `out` (written in `dir`).
Decoded render_to_tev(const test::TempDir& dir, const std::string& args, const std::string& out) {
    TevListener tev;
    const std::string cmd = std::string(FOTON_BINARY) + " render " + args + " -q --display " +
                            tev.address() + " -o " + dir.file(out);
    REQUIRE(std::system(cmd.c_str()) == 0);
    return decode(tev.received(), out);
}

// Every value of the named channels as tev got them equals the EXR's.
void check_planes_equal_exr(const Decoded& d, const std::string& exr_path,
                            const std::vector<std::string>& names) {
    int w = 0, h = 0;
    const std::vector<float> exr = read_exr_channels(exr_path, names, w, h);
    REQUIRE(w == d.width);
    REQUIRE(h == d.height);
    for (std::size_t c = 0; c < names.size(); ++c)
        for (std::size_t p = 0; p < std::size_t(w * h); ++p)
            CHECK(d.planes.at(names[c])[p] == exr[p * names.size() + c]);
}

}  // namespace

TEST_CASE("foton render --display --aov: the AOVs reach tev as channels", "[tev][cli][aov]") {
    test::TempDir dir;
    const Decoded d = render_to_tev(dir,
                                    test::source_path("scenes/cornell-diffuse.xml") +
                                        " --width 20 --height 14 --spp 2 --integrator path --aov "
                                        "albedo,depth,samples",
                                    "aov.exr");
    CHECK(d.channels == std::vector<std::string>{"R", "G", "B", "Albedo.R", "Albedo.G", "Albedo.B",
                                                 "Z", "samples"});
    REQUIRE(d.planes.size() == 5);
    check_planes_equal_exr(d, dir.file("aov.exr"),
                           {"Albedo.R", "Albedo.G", "Albedo.B", "Z", "samples"});
}

TEST_CASE("foton render --display: layers named after the render make the image again",
          "[tev][cli][aov]") {
    test::TempDir dir;
    const Decoded d = render_to_tev(
        dir,
        test::source_path("scenes/cornell-caustics.xml") +
            " --width 20 --height 14 --spp 1 --integrator photon --aov depth,components --set "
            "global_photons=5000 --set caustic_photons=5000",
        "parts.exr");
    // Made with R, G, B and Z, then again with the components the photon mapper names.
    CHECK(d.channels == std::vector<std::string>{"R", "G", "B", "Z", "emitted.R", "emitted.G",
                                                 "emitted.B", "direct.R", "direct.G", "direct.B",
                                                 "caustic.R", "caustic.G", "caustic.B",
                                                 "indirect.R", "indirect.G", "indirect.B"});
    REQUIRE_FALSE(d.images.empty());
    CHECK(same(d.images.back(), read_exr(dir.file("parts.exr"))));
    check_planes_equal_exr(d, dir.file("parts.exr"), {"Z", "caustic.G", "indirect.B"});
}

TEST_CASE("foton render --display with no viewer: one warning, the render goes on", "[tev][cli]") {
    test::TempDir dir;
    int port = 0;
    {
        TevListener closed;  // a port that was free a moment ago, now with no one listening
        port = std::stoi(closed.address().substr(10));
    }
    const std::string cmd =
        std::string(FOTON_BINARY) + " render " + test::source_path("scenes/cornell-diffuse.xml") +
        " --width 16 --height 16 --passes 3 -q --display 127.0.0.1:" + std::to_string(port) +
        " -o " + dir.file("n.exr") + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    const int status = pclose(p);
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(std::filesystem::exists(dir.file("n.exr")));
    const std::size_t first = out.find("cannot connect");
    CHECK(first != std::string::npos);
    CHECK(out.find("cannot connect", first + 1) == std::string::npos);
    // A malformed address is bad input, before any work.
    const std::string bad = std::string(FOTON_BINARY) + " render " +
                            test::source_path("scenes/cornell-diffuse.xml") +
                            " --display nocolon -q -o " + dir.file("b.exr") + " 2>/dev/null";
    CHECK(WEXITSTATUS(std::system(bad.c_str())) == 2);
    CHECK_FALSE(std::filesystem::exists(dir.file("b.exr")));
}
