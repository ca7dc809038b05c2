// glTF accessors read with every index, offset and stride checked (gltf_accessors.h).
#include "gltf_accessors.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"

namespace foton {

void GltfAccessors::fail(const std::string& where, const std::string& what) const {
    throw InputError(path_, 0, where + ": " + what);
}

std::vector<float> GltfAccessors::floats(int a, int n, const std::string& where) const {
    std::vector<float> out;
    read(a, n, where, false, [&](double v) { out.push_back(float(v)); });
    return out;
}
std::vector<uint32_t> GltfAccessors::indices(int a, const std::string& where) const {
    std::vector<uint32_t> out;
    read(a, 1, where, true, [&](double v) { out.push_back(uint32_t(v)); });
    return out;
}

void GltfAccessors::read(int a, int n, const std::string& where, bool as_index,
                         const std::function<void(double)>& put) const {
    if (a < 0 || std::size_t(a) >= g_.accessors.size())
        fail(where, "accessor " + std::to_string(a) + " does not exist");
    const tinygltf::Accessor& acc = g_.accessors[std::size_t(a)];
    const std::string at = where + ", accessor " + std::to_string(a);
    if (tinygltf::GetNumComponentsInType(uint32_t(acc.type)) != n)
        fail(at, "has " + std::to_string(tinygltf::GetNumComponentsInType(uint32_t(acc.type))) +
                     " components, expected " + std::to_string(n));
    const int ct = acc.componentType;
    // Core glTF: floats, or normalised unsigned bytes and shorts (uv, colours);
    // KHR_mesh_quantization adds signed ones and integers read as they are.
    const bool small_int = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                           ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                           ct == TINYGLTF_COMPONENT_TYPE_BYTE ||
                           ct == TINYGLTF_COMPONENT_TYPE_SHORT;
    const bool core = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                      (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                          ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
    const bool ok_type = as_index ? is_index_type(ct) : core || (quantized_ && small_int);
    if (!ok_type)
        fail(at, "component type " + std::to_string(ct) + " is not allowed here" +
                     (small_int && !quantized_ ? " (the file does not use KHR_mesh_quantization)"
                                               : ""));
    const bool to_unit = !as_index && acc.normalized;
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(ct));
    const uint64_t element = uint64_t(size) * uint64_t(n);
    // The dense elements (a sparse accessor may have none: zeros then).
    const unsigned char* base = nullptr;
    uint64_t stride = element;
    if (acc.bufferView >= 0 || !acc.sparse.isSparse) {
        const tinygltf::BufferView& view = buffer_view(acc.bufferView, at);
        const int s = acc.ByteStride(view);
        if (s <= 0 || size <= 0) fail(at, "invalid byte stride");
        stride = uint64_t(s);
        base = view_bytes(view, acc.byteOffset, acc.count, stride, element, at);
    } else if (acc.count > kMaxSparseOnlyElements) {
        fail(at, "a sparse accessor without a bufferView may hold at most " +
                     std::to_string(kMaxSparseOnlyElements) + " elements");
    }
    // A sparse accessor's substitutions: strictly increasing element indices, each with
    // its n components (tightly packed, the accessor's component type).
    std::vector<uint64_t> sub_at;
    const unsigned char* sub_values = nullptr;
    if (acc.sparse.isSparse) {
        const int sc = acc.sparse.count;
        const auto& si = acc.sparse.indices;
        if (sc < 1 || uint64_t(sc) > acc.count) fail(at, "sparse count must be in [1, count]");
        if (!is_index_type(si.componentType)) fail(at, "sparse indices must be unsigned integers");
        const uint64_t isz =
            uint64_t(tinygltf::GetComponentSizeInBytes(uint32_t(si.componentType)));
        const unsigned char* ib =
            view_bytes(buffer_view(si.bufferView, at + " sparse indices"), uint64_t(si.byteOffset),
                       uint64_t(sc), isz, isz, at + " sparse indices");
        for (int k = 0; k < sc; ++k) {
            const uint64_t i =
                uint64_t(component(ib + uint64_t(k) * isz, si.componentType, false, at));
            if (i >= acc.count || (!sub_at.empty() && i <= sub_at.back()))
                fail(at, "sparse indices must increase and stay below count");
            sub_at.push_back(i);
        }
        sub_values = view_bytes(buffer_view(acc.sparse.values.bufferView, at + " sparse values"),
                                uint64_t(acc.sparse.values.byteOffset), uint64_t(sc), element,
                                element, at + " sparse values");
    }
    std::size_t next = 0;
    for (std::size_t i = 0; i < acc.count; ++i) {
        const unsigned char* e = base ? base + i * stride : nullptr;
        if (next < sub_at.size() && sub_at[next] == i) e = sub_values + element * next++;
        for (int k = 0; k < n; ++k)
            put(e ? component(e + std::size_t(k * size), ct, to_unit, at) : 0.0);
    }
}

bool GltfAccessors::is_index_type(int ct) {
    return ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

const tinygltf::BufferView& GltfAccessors::buffer_view(int bv, const std::string& at) const {
    if (bv < 0 || std::size_t(bv) >= g_.bufferViews.size()) fail(at, "has no valid bufferView");
    const tinygltf::BufferView& view = g_.bufferViews[std::size_t(bv)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= g_.buffers.size())
        fail(at, "its bufferView names no valid buffer");
    const std::vector<unsigned char>& data = g_.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
        fail(at, "its bufferView lies outside the buffer");
    return view;
}

const unsigned char* GltfAccessors::view_bytes(const tinygltf::BufferView& view, uint64_t offset,
                                               uint64_t count, uint64_t stride, uint64_t element,
                                               const std::string& at) const {
    if (count > 0) {
        // (count and stride come from the file: the product must not wrap.)
        if (count - 1 > (uint64_t(1) << 40) / std::max<uint64_t>(stride, 1))
            fail(at, "reads beyond its bufferView");
        const uint64_t last = offset + (count - 1) * stride + element;
        if (last > view.byteLength) fail(at, "reads beyond its bufferView");
    }
    return g_.buffers[std::size_t(view.buffer)].data.data() + view.byteOffset + offset;
}

double GltfAccessors::component(const unsigned char* c, int ct, bool to_unit,
                                const std::string& at) const {
    switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float f;
            std::memcpy(&f, c, 4);
            if (!std::isfinite(f)) fail(at, "holds NaN or infinite values");
            return f;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return to_unit ? double(*c) / 255.0 : double(*c);
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const double v = double(int8_t(*c));
            return to_unit ? std::max(v / 127.0, -1.0) : v;  // the spec's signed mapping
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t s;
            std::memcpy(&s, c, 2);
            return to_unit ? double(s) / 65535.0 : double(s);
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t s;
            std::memcpy(&s, c, 2);
            return to_unit ? std::max(double(s) / 32767.0, -1.0) : double(s);
        }
        default: {
            uint32_t u;
            std::memcpy(&u, c, 4);
            return double(u);
        }
    }
}

}  // namespace foton
