// libFuzzer target: any bytes as a target JSON file (`slicecap target --json`, docs/recording-
// format.md). readTargetJson either returns a target, which writeTargetJson writes and
// readTargetJson reads back equal, or throws io::IoError naming the file and field (the error a
// person sees); anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_file.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap;
  static const std::filesystem::path dir = fuzz::scratchDir("target");
  static const std::filesystem::path file = dir / "target.json", again = dir / "again.json";
  fuzz::writeBytes(file, fuzz::asText(data, size));
  vision::TargetGeometry target;
  try {
    target = io::readTargetJson(file);
  } catch (const io::IoError&) {
    return 0;
  }
  io::writeTargetJson(again, target);
  if (!(io::readTargetJson(again) == target)) std::abort();
  return 0;
}
