#pragma once
// Live preview in tev (https://github.com/Tom94/tev), the HDR viewer: the image so far is
// streamed over tev's TCP protocol after every pass. Sending runs on a thread of its own and
// keeps only the newest image, so a slow viewer never slows the render; when no tev is
// listening (or it goes away) the render warns once and carries on.
//
// The packets (little-endian): uint32 size of the whole packet, a type byte, then fields;
// strings are NUL-terminated. CloseImage (2): name. CreateImage (4): grabFocus byte, name,
// int32 width, height, channel count, channel names. UpdateImage v3 (6): grabFocus byte,
// name, int32 channel count, channel names, int32 x, y, width, height, int64 offset and
// stride per channel, then the floats.
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/film/aov.h"
#include "engine/film/film.h"

namespace foton::app {

namespace tev {
enum class PacketType : uint8_t { CloseImage = 2, CreateImage = 4, UpdateImage = 6 };
std::vector<char> close_image(const std::string& name);
// An image of the given channels (R, G, B, then any AOV channels).
std::vector<char> create_image(const std::string& name, int width, int height,
                               const std::vector<std::string>& channels = {"R", "G", "B"});
// Rows [y0, y1) of `film` as R, G, B channels.
std::vector<char> update_image(const std::string& name, const Film& film, int y0, int y1);
// Rows [y0, y1) of an AOV layer of an image `width` pixels wide.
std::vector<char> update_layer(const std::string& name, const AovLayer& layer, int width, int y0,
                               int y1);
}  // namespace tev

class TevDisplay {
  public:
    // `address` is HOST:PORT (bad input otherwise). `name` is the image's name in tev;
    // `aov_channels` the channels it has beside R, G, B (film/aov.h's).
    TevDisplay(const std::string& address, std::string name, int width, int height,
               std::vector<std::string> aov_channels = {});
    ~TevDisplay();  // sends what is queued, then disconnects
    TevDisplay(const TevDisplay&) = delete;
    TevDisplay& operator=(const TevDisplay&) = delete;

    // Queues `film` for sending, replacing an image not yet sent.
    void show(const Film& film);
    // Queues the AOV layers, sent after the image queued before them; channels the image was
    // not created with make it again with them.
    void show_layers(std::vector<AovLayer> layers);
    // Returns when everything queued has been sent (or the connection has failed).
    void flush();
    // Images sent in full so far.
    std::size_t sent() const;

  private:
    void run();
    bool connect_once();
    bool send_all(const std::vector<char>& packet);

    std::string host_, port_, name_;
    int width_, height_;
    int socket_ = -1;
    bool failed_ = false;
    mutable std::mutex mutex_;
    std::condition_variable wake_, idle_;
    std::vector<std::string> aov_channels_;
    std::vector<std::string> channels_;  // the image's channels in tev (the sender's thread)
    std::optional<Film> last_;           // the last image sent (the sender's thread)
    std::optional<Film> pending_;
    std::vector<AovLayer> pending_layers_;
    bool busy_ = false, stop_ = false;
    std::size_t sent_ = 0;
    std::thread thread_;
};

}  // namespace foton::app
