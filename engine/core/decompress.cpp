#include "decompress.h"

#include <lzma.h>
#include <zlib.h>

#include <algorithm>

#include "error.h"
#include "input_file.h"

namespace foton {

namespace {

constexpr std::size_t kChunk = std::size_t(1) << 20;

std::string too_large(uint64_t max_bytes) {
    return "decompresses to more than the " + std::to_string(max_bytes >> 20) + " MiB allowed";
}

std::string gunzip(const std::string& data, const std::string& path, uint64_t max_bytes) {
    z_stream zs{};
    // 16 + MAX_WBITS: a gzip header and trailer (whose CRC and size inflate checks).
    if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK)
        throw InputError(path, 0, "cannot start gzip decompression");
    std::string out;
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    std::size_t left = data.size();
    int rc = Z_OK;
    try {
        while (rc != Z_STREAM_END) {
            if (zs.avail_in == 0 && left > 0) {
                const std::size_t n = std::min<std::size_t>(left, 1u << 30);
                zs.avail_in = uInt(n);
                left -= n;
            }
            const std::size_t at = out.size();
            out.resize(at + kChunk);
            zs.next_out = reinterpret_cast<Bytef*>(out.data() + at);
            zs.avail_out = uInt(kChunk);
            rc = inflate(&zs, Z_NO_FLUSH);
            out.resize(at + (kChunk - zs.avail_out));
            if (out.size() > max_bytes) throw InputError(path, 0, too_large(max_bytes));
            if (rc == Z_STREAM_END) break;
            if (rc == Z_BUF_ERROR && zs.avail_in == 0 && left == 0)
                throw InputError(path, 0, "truncated gzip data (the file ends too early)");
            if (rc != Z_OK)
                throw InputError(path, 0,
                                 std::string("corrupt gzip data: ") +
                                     (zs.msg ? zs.msg : "inflate error " + std::to_string(rc)));
        }
    } catch (...) {
        inflateEnd(&zs);
        throw;
    }
    inflateEnd(&zs);
    return out;
}

std::string unxz(const std::string& data, const std::string& path, uint64_t max_bytes) {
    lzma_stream ls = LZMA_STREAM_INIT;
    if (lzma_stream_decoder(&ls, UINT64_MAX, LZMA_CONCATENATED) != LZMA_OK)
        throw InputError(path, 0, "cannot start xz decompression");
    std::string out;
    ls.next_in = reinterpret_cast<const uint8_t*>(data.data());
    ls.avail_in = data.size();
    try {
        for (;;) {
            const std::size_t at = out.size();
            out.resize(at + kChunk);
            ls.next_out = reinterpret_cast<uint8_t*>(out.data() + at);
            ls.avail_out = kChunk;
            const lzma_ret rc = lzma_code(&ls, LZMA_FINISH);
            out.resize(at + (kChunk - ls.avail_out));
            if (out.size() > max_bytes) throw InputError(path, 0, too_large(max_bytes));
            if (rc == LZMA_STREAM_END) break;
            if (rc == LZMA_OK) continue;
            if (rc == LZMA_BUF_ERROR)
                throw InputError(path, 0, "truncated xz data (the file ends too early)");
            if (rc == LZMA_FORMAT_ERROR) throw InputError(path, 0, "not xz data");
            throw InputError(path, 0,
                             "corrupt xz data (liblzma error " + std::to_string(int(rc)) + ")");
        }
    } catch (...) {
        lzma_end(&ls);
        throw;
    }
    lzma_end(&ls);
    return out;
}

}  // namespace

bool is_compressed_input(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".gz" || ext == ".xz";
}

std::string decompress_input(const std::string& data, const std::string& path, uint64_t max_bytes) {
    if (lower_extension(path) == ".xz") return unxz(data, path, max_bytes);
    return gunzip(data, path, max_bytes);
}

std::string read_input_file_decompressed(const std::string& path, uint64_t max_bytes,
                                         const char* what) {
    std::string data = read_input_file(path, max_bytes, what);
    if (!is_compressed_input(path)) return data;
    return decompress_input(data, path, max_bytes);
}

}  // namespace foton
