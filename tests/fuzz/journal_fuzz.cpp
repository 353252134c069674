// libFuzzer target: any bytes as a session's journal (lib/io journal.hpp, replayed by
// capture::SessionStore::open, as the daemon does after a restart). Each input is tried twice:
// as it is (torn tails, damaged checksums), and with every complete line's checksum made valid,
// so that the records themselves reach the replay. Opening either gives a session whose samples
// can be combined, or throws io::IoError naming the journal (the error a person sees); anything
// else is a bug.
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "fuzz_file.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace {

// Every complete line as "<crc32 hex8> <record>": a line that already starts with eight hex
// digits and a space keeps its record and gets the right checksum, any other line becomes a
// record. An unfinished last line (a torn tail) stays as it is.
std::string withValidChecksums(std::string_view input) {
  std::string out;
  std::size_t start = 0;
  while (start < input.size()) {
    const std::size_t newline = input.find('\n', start);
    if (newline == std::string_view::npos) {
      out += input.substr(start);
      break;
    }
    std::string_view record = input.substr(start, newline - start);
    bool framed = record.size() >= 9 && record[8] == ' ';
    for (std::size_t i = 0; framed && i < 8; ++i)
      framed = std::isxdigit(static_cast<unsigned char>(record[i])) != 0;
    if (framed) record.remove_prefix(9);
    char crc[9];
    std::snprintf(crc, sizeof crc, "%08x", slicecap::io::crc32(record));
    out.append(crc).append(" ").append(record).append("\n");
    start = newline + 1;
  }
  return out;
}

void replay(const std::filesystem::path& root, std::string_view journal) {
  using namespace slicecap;
  fuzz::writeBytes(root / "s" / "journal", journal);
  try {
    const capture::SessionStore store = capture::SessionStore::open(root, "s");
    const SliceSet slices = store.slices();
    (void)store.sampleCount();
    (void)store.activeSweep();
  } catch (const io::IoError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap;
  static const std::filesystem::path root = [] {
    const std::filesystem::path made = fuzz::scratchDir("journal") / "sessions";
    capture::SessionStore::create(made, "s", "fuzzed material");
    return made;
  }();
  const std::string_view input = fuzz::asText(data, size);
  replay(root, input);
  replay(root, withValidChecksums(input));
  return 0;
}
