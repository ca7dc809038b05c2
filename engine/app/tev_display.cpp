#include "tev_display.h"

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "engine/core/error.h"

namespace foton::app {

namespace tev {
namespace {

// A packet under construction; the size field is filled in by finish().
class Packet {
  public:
    explicit Packet(PacketType type) {
        put_raw(uint32_t(0));
        bytes_.push_back(char(type));
    }
    void put_bool(bool v) { bytes_.push_back(v ? 1 : 0); }
    void put_string(const std::string& s) {
        bytes_.insert(bytes_.end(), s.c_str(), s.c_str() + s.size() + 1);
    }
    template <typename T>
    void put_raw(T v) {
        // tev reads integers little-endian; foton runs on little-endian machines only.
        const char* p = reinterpret_cast<const char*>(&v);
        bytes_.insert(bytes_.end(), p, p + sizeof v);
    }
    std::vector<char> finish() {
        const uint32_t size = uint32_t(bytes_.size());
        std::memcpy(bytes_.data(), &size, sizeof size);
        return std::move(bytes_);
    }

  private:
    std::vector<char> bytes_;
};

constexpr const char* kChannels[3] = {"R", "G", "B"};

// The UpdateImage header: the channels, the rectangle, and each channel's offset and stride in
// the floats that follow (pixel-interleaved, `channels.size()` floats a pixel).
void put_update_header(Packet& p, const std::string& name, const std::vector<std::string>& channels,
                       int width, int y0, int y1) {
    p.put_bool(false);
    p.put_string(name);
    p.put_raw(int32_t(channels.size()));
    for (const std::string& c : channels) p.put_string(c);
    p.put_raw(int32_t(0));
    p.put_raw(int32_t(y0));
    p.put_raw(int32_t(width));
    p.put_raw(int32_t(y1 - y0));
    for (std::size_t c = 0; c < channels.size(); ++c) p.put_raw(int64_t(c));
    for (std::size_t c = 0; c < channels.size(); ++c) p.put_raw(int64_t(channels.size()));
}

}  // namespace

std::vector<char> close_image(const std::string& name) {
    Packet p(PacketType::CloseImage);
    p.put_string(name);
    return p.finish();
}

std::vector<char> create_image(const std::string& name, int width, int height,
                               const std::vector<std::string>& channels) {
    Packet p(PacketType::CreateImage);
    p.put_bool(true);
    p.put_string(name);
    p.put_raw(int32_t(width));
    p.put_raw(int32_t(height));
    p.put_raw(int32_t(channels.size()));
    for (const std::string& c : channels) p.put_string(c);
    return p.finish();
}

std::vector<char> update_image(const std::string& name, const Film& film, int y0, int y1) {
    Packet p(PacketType::UpdateImage);
    // The film's pixels are interleaved R, G, B floats.
    put_update_header(p, name, {kChannels[0], kChannels[1], kChannels[2]}, film.width, y0, y1);
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < film.width; ++x) {
            const RGB& v = film.at(x, y);
            p.put_raw(v.r);
            p.put_raw(v.g);
            p.put_raw(v.b);
        }
    return p.finish();
}

std::vector<char> update_layer(const std::string& name, const AovLayer& layer, int width, int y0,
                               int y1) {
    Packet p(PacketType::UpdateImage);
    put_update_header(p, name, layer.channels, width, y0, y1);
    const std::size_t begin = std::size_t(y0) * std::size_t(width) * layer.stride();
    const std::size_t end = std::size_t(y1) * std::size_t(width) * layer.stride();
    for (std::size_t i = begin; i < end; ++i) p.put_raw(layer.values[i]);
    return p.finish();
}

}  // namespace tev

TevDisplay::TevDisplay(const std::string& address, std::string name, int width, int height,
                       std::vector<std::string> aov_channels)
    : name_(std::move(name)),
      width_(width),
      height_(height),
      aov_channels_(std::move(aov_channels)) {
    const auto colon = address.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == address.size())
        throw InputError("--display", 0, "expected HOST:PORT, got '" + address + "'");
    host_ = address.substr(0, colon);
    port_ = address.substr(colon + 1);
    if (!std::all_of(port_.begin(), port_.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
        port_.size() > 5 || std::stoi(port_) > 65535)
        throw InputError("--display", 0, "bad port '" + port_ + "' in '" + address + "'");
    thread_ = std::thread([this] { run(); });
}

TevDisplay::~TevDisplay() {
    flush();
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
    if (socket_ >= 0) close(socket_);
}

void TevDisplay::show(const Film& film) {
    {
        std::lock_guard lock(mutex_);
        if (failed_) return;
        pending_ = film;
    }
    wake_.notify_one();
}

void TevDisplay::show_layers(std::vector<AovLayer> layers) {
    {
        std::lock_guard lock(mutex_);
        if (failed_) return;
        for (AovLayer& l : layers) pending_layers_.push_back(std::move(l));
    }
    wake_.notify_one();
}

void TevDisplay::flush() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock,
               [this] { return failed_ || (!pending_ && pending_layers_.empty() && !busy_); });
}

std::size_t TevDisplay::sent() const {
    std::lock_guard lock(mutex_);
    return sent_;
}

bool TevDisplay::connect_once() {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const int err = getaddrinfo(host_.c_str(), port_.c_str(), &hints, &found);
    if (err != 0) {
        std::fprintf(stderr, "foton: --display %s:%s: %s; rendering without the preview\n",
                     host_.c_str(), port_.c_str(), gai_strerror(err));
        return false;
    }
    int last_errno = 0;
    for (addrinfo* a = found; a && socket_ < 0; a = a->ai_next) {
        const int s = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (s < 0) continue;
        if (connect(s, a->ai_addr, a->ai_addrlen) == 0) {
            socket_ = s;
        } else {
            last_errno = errno;
            close(s);
        }
    }
    freeaddrinfo(found);
    if (socket_ < 0) {
        std::fprintf(stderr,
                     "foton: --display %s:%s: cannot connect (%s); is tev running? Rendering "
                     "without the preview\n",
                     host_.c_str(), port_.c_str(), std::strerror(last_errno));
        return false;
    }
    channels_ = {"R", "G", "B"};
    channels_.insert(channels_.end(), aov_channels_.begin(), aov_channels_.end());
    return send_all(tev::close_image(name_)) &&
           send_all(tev::create_image(name_, width_, height_, channels_));
}

bool TevDisplay::send_all(const std::vector<char>& packet) {
    std::size_t done = 0;
    while (done < packet.size()) {
        // MSG_NOSIGNAL: a viewer that went away is an error here, not a SIGPIPE.
        const ssize_t n = send(socket_, packet.data() + done, packet.size() - done, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            std::fprintf(stderr,
                         "foton: --display %s:%s: the viewer went away (%s); rendering on "
                         "without the preview\n",
                         host_.c_str(), port_.c_str(), std::strerror(errno));
            return false;
        }
        done += std::size_t(n);
    }
    return true;
}

void TevDisplay::run() {
    const bool connected = connect_once();
    std::unique_lock lock(mutex_);
    if (!connected) {
        failed_ = true;
        pending_.reset();
        pending_layers_.clear();
        idle_.notify_all();
        return;
    }
    for (;;) {
        wake_.wait(lock, [this] { return stop_ || pending_ || !pending_layers_.empty(); });
        if (!pending_ && pending_layers_.empty()) break;  // stopping with nothing left to send
        std::optional<Film> film = std::move(pending_);
        pending_.reset();
        // Layers queued after this image go with it; a later image waits for the next round.
        std::vector<AovLayer> layers = std::move(pending_layers_);
        pending_layers_.clear();
        busy_ = true;
        lock.unlock();
        // Bands of rows, a few hundred thousand floats each, keep packets moderate.
        auto rows = [&](std::size_t channels) {
            return std::max(1, int(786432 / (std::max(width_, 1) * channels)));
        };
        bool ok = true;
        // Layers of channels the image lacks (the per-strategy images, the components, named
        // only once the render has made them): the image is made again with them, and the
        // last image sent goes first.
        std::vector<std::string> added;
        for (const AovLayer& l : layers)
            for (const std::string& c : l.channels)
                if (std::find(channels_.begin(), channels_.end(), c) == channels_.end() &&
                    std::find(added.begin(), added.end(), c) == added.end())
                    added.push_back(c);
        if (!added.empty()) {
            channels_.insert(channels_.end(), added.begin(), added.end());
            ok = send_all(tev::close_image(name_)) &&
                 send_all(tev::create_image(name_, width_, height_, channels_));
            if (!film) film = last_;
        }
        if (film)
            for (int y = 0, n = rows(3); ok && y < film->height; y += n)
                ok = send_all(tev::update_image(name_, *film, y, std::min(film->height, y + n)));
        if (film) last_ = std::move(film);  // sent: kept for a remake, not copied
        for (const AovLayer& l : layers)
            for (int y = 0, n = rows(l.stride()); ok && y < height_; y += n)
                ok = send_all(tev::update_layer(name_, l, width_, y, std::min(height_, y + n)));
        lock.lock();
        busy_ = false;
        if (!ok) {
            failed_ = true;
            pending_.reset();
            pending_layers_.clear();
            idle_.notify_all();
            return;
        }
        if (film) ++sent_;
        if (!pending_ && pending_layers_.empty()) idle_.notify_all();
    }
}

}  // namespace foton::app
