// libFuzzer target: any bytes as a prior file (docs/reference/file-formats.md). readPriorModel
// either returns a model whose arrays have the sizes its header gave, or throws PriorError naming
// the file (the error a person sees); anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_file.hpp"
#include "slicecap/prior/prior_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap;
  static const std::filesystem::path file = fuzz::scratchDir("prior") / "prior.bin";
  fuzz::writeBytes(file, fuzz::asText(data, size));
  try {
    const prior::PriorModel model = prior::readPriorModel(file);
    if (model.components() < 1 || model.mean.size() != std::size_t(prior::kFeatureCount) ||
        model.basis.size() != std::size_t(model.components()) * prior::kFeatureCount)
      std::abort();
  } catch (const prior::PriorError&) {
  }
  return 0;
}
