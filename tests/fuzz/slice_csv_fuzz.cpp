// libFuzzer target: any bytes as a slice CSV. The reader either returns slices or throws
// io::IoError (the error a person sees); anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/slice_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const slicecap::SliceSet slices = slicecap::io::parseSliceCsv(in, "fuzz.csv");
    std::ostringstream out;
    slicecap::io::writeSliceCsv(out, slices);
  } catch (const slicecap::io::IoError&) {
  }
  return 0;
}
