// The prior file: a small little-endian binary (magic, sizes, provenance text, float32 arrays).
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {
namespace {

static_assert(std::endian::native == std::endian::little, "the prior file is little-endian");
constexpr char kMagic[8] = {'S', 'L', 'C', 'P', 'R', 'I', 'O', 'R'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kMaxProvenance = 1 << 16;

template <typename T>
void put(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

void writePriorModel(const std::filesystem::path& path, const PriorModel& model) {
  const std::uint32_t components = static_cast<std::uint32_t>(model.components());
  if (model.mean.size() != std::size_t(kFeatureCount) ||
      model.basis.size() != std::size_t(components) * kFeatureCount ||
      model.provenance.size() > kMaxProvenance) {
    throw PriorError(path.string() + ": inconsistent prior model, not written");
  }
  try {
    io::writeStreamReplacing(path, [&](std::ostream& out) {
      out.write(kMagic, sizeof kMagic);
      put(out, kVersion);
      put(out, std::uint32_t(kFeatureCount));
      put(out, components);
      put(out, model.floorFraction);
      put(out, model.residualVariance);
      put(out, std::uint32_t(model.provenance.size()));
      out.write(model.provenance.data(), std::streamsize(model.provenance.size()));
      for (const auto* array : {&model.mean, &model.variance, &model.basis})
        out.write(reinterpret_cast<const char*>(array->data()),
                  std::streamsize(array->size() * sizeof(float)));
    });
  } catch (const io::IoError& e) {
    throw PriorError(e.what());  // the prior's one documented error type; it names the path
  }
}

PriorModel readPriorModel(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PriorError(path.string() + ": cannot open the prior file");
  auto fail = [&](const std::string& what) { return PriorError(path.string() + ": " + what); };
  auto get = [&](auto& value, const char* field) {
    in.read(reinterpret_cast<char*>(&value), sizeof value);
    if (!in) throw fail(std::string("truncated at ") + field);
  };
  char magic[8];
  in.read(magic, sizeof magic);
  if (!in || std::memcmp(magic, kMagic, sizeof magic) != 0)
    throw fail("not a slicecap prior file (bad magic)");
  std::uint32_t version = 0, features = 0, components = 0, provenanceSize = 0;
  PriorModel model;
  get(version, "version");
  if (version != kVersion)
    throw fail("version " + std::to_string(version) + " is not supported (expected 1)");
  get(features, "feature count");
  if (features != std::uint32_t(kFeatureCount))
    throw fail("feature count " + std::to_string(features) + " is not 81 x 81");
  get(components, "components");
  if (components < 1 || components > 256)
    throw fail("components " + std::to_string(components) + " outside 1..256");
  get(model.floorFraction, "floor fraction");
  if (!(model.floorFraction > 0.0 && model.floorFraction < 1.0))
    throw fail("floor fraction outside (0, 1)");
  get(model.residualVariance, "residual variance");
  if (!(model.residualVariance > 0.0) || !std::isfinite(model.residualVariance))
    throw fail("residual variance is not a positive number");
  get(provenanceSize, "provenance length");
  if (provenanceSize > kMaxProvenance) throw fail("provenance text too long");
  model.provenance.resize(provenanceSize);
  in.read(model.provenance.data(), provenanceSize);
  if (!in) throw fail("truncated at provenance");
  model.mean.resize(kFeatureCount);
  model.variance.resize(components);
  model.basis.resize(std::size_t(components) * kFeatureCount);
  for (auto [array, field] :
       {std::pair{&model.mean, "mean"}, std::pair{&model.variance, "variance"},
        std::pair{&model.basis, "basis"}}) {
    in.read(reinterpret_cast<char*>(array->data()), std::streamsize(array->size() * sizeof(float)));
    if (!in) throw fail(std::string("truncated at ") + field);
    for (float v : *array) {
      if (!std::isfinite(v)) throw fail(std::string("non-finite value in ") + field);
    }
  }
  for (float v : model.variance) {
    if (!(v > 0.0f)) throw fail("a component variance is not positive");
  }
  if (in.peek() != std::char_traits<char>::eof()) throw fail("trailing bytes after the basis");
  return model;
}

}  // namespace slicecap::prior
