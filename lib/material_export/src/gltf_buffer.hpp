// A glTF 2.0 buffer being laid out: vertex attributes and indices as buffer views and accessors
// (glTF 2.0 specification, "Buffers and Buffer Views", "Accessors"), shared by the preview meshes
// and the textured plane.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

namespace slicecap::material_export::gltf_buffer {

using json = nlohmann::ordered_json;

inline constexpr int kFloat = 5126, kUnsignedInt = 5125;
inline constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

class BufferBuilder {
 public:
  // Appends `data` as a buffer view and an accessor over it; returns the accessor's index.
  template <typename T, std::size_t N>
  int addVectors(const std::vector<std::array<T, N>>& data, int componentType, const char* type,
                 bool withBounds) {
    const int view = addView(data.data(), data.size() * sizeof(std::array<T, N>), kArrayBuffer);
    json accessor = {{"bufferView", view},
                     {"componentType", componentType},
                     {"count", data.size()},
                     {"type", type}};
    if (withBounds) {
      // POSITION must carry min and max (glTF 2.0, "Meshes": accessor bounds).
      std::array<T, N> low, high;
      low.fill(std::numeric_limits<T>::max());
      high.fill(std::numeric_limits<T>::lowest());
      for (const auto& v : data)
        for (std::size_t i = 0; i < N; ++i) {
          low[i] = std::min(low[i], v[i]);
          high[i] = std::max(high[i], v[i]);
        }
      accessor["min"] = low;
      accessor["max"] = high;
    }
    accessors.push_back(accessor);
    return static_cast<int>(accessors.size()) - 1;
  }

  int addIndices(const std::vector<std::uint32_t>& indices) {
    const int view = addView(indices.data(), indices.size() * sizeof(std::uint32_t),
                             kElementArrayBuffer);
    accessors.push_back({{"bufferView", view},
                         {"componentType", kUnsignedInt},
                         {"count", indices.size()},
                         {"type", "SCALAR"}});
    return static_cast<int>(accessors.size()) - 1;
  }

  std::vector<std::uint8_t> bytes;
  json views = json::array();
  json accessors = json::array();

 private:
  int addView(const void* data, std::size_t size, int target) {
    // Every element here is 4 bytes wide: 4-byte alignment satisfies the accessor rules.
    while (bytes.size() % 4 != 0) bytes.push_back(0);
    const std::size_t offset = bytes.size();
    bytes.resize(offset + size);
    std::memcpy(bytes.data() + offset, data, size);
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}, {"target", target}});
    return static_cast<int>(views.size()) - 1;
  }
};

}  // namespace slicecap::material_export::gltf_buffer
