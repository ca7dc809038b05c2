#pragma once
// glTF's accessors (dense, sparse, or sparse over zeros) read into floats or indices. Every
// index, offset and stride tinygltf hands over is checked before use, so a malformed file is an
// InputError naming the file and accessor, never a read out of bounds.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
struct BufferView;
}  // namespace tinygltf

namespace foton {

class GltfAccessors {
  public:
    // `quantized`: the file uses KHR_mesh_quantization (integer positions, normals, uv).
    GltfAccessors(const tinygltf::Model& model, const std::string& path, bool quantized)
        : g_(model), path_(path), quantized_(quantized) {}

    // The elements of accessor `a`, `n` components each, as floats (normalised integers mapped
    // to [0, 1], signed ones to [-1, 1], other integers as they are) or as vertex indices;
    // `where` names what reads it in errors.
    std::vector<float> floats(int a, int n, const std::string& where) const;
    std::vector<uint32_t> indices(int a, const std::string& where) const;

  private:
    // Each component of each element of accessor `a` in order, sparse substitutions applied.
    void read(int a, int n, const std::string& where, bool as_index,
              const std::function<void(double)>& put) const;
    static bool is_index_type(int ct);
    const tinygltf::BufferView& buffer_view(int bv, const std::string& at) const;
    // The first of `count` elements of `element` bytes, `stride` apart from `offset` in the
    // view, each checked to lie inside it.
    const unsigned char* view_bytes(const tinygltf::BufferView& view, uint64_t offset,
                                    uint64_t count, uint64_t stride, uint64_t element,
                                    const std::string& at) const;
    // One component at c: a float (finite), an integer, or (to_unit) a normalised integer.
    double component(const unsigned char* c, int ct, bool to_unit, const std::string& at) const;
    [[noreturn]] void fail(const std::string& where, const std::string& what) const;

    // Elements of a sparse accessor with no dense data: its count is not bounded by a buffer.
    static constexpr uint64_t kMaxSparseOnlyElements = uint64_t(1) << 24;
    const tinygltf::Model& g_;
    std::string path_;
    bool quantized_;
};

}  // namespace foton
