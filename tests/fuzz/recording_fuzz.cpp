// libFuzzer target: any bytes as a recording's recording.json (docs/recording-format.md), read
// with the camera, the embedded target and the frame list. The recording's folder holds
// frame-00000.png .. frame-00003.png and a valid camera.json, so that manifests naming them get
// past the file checks. readRecording either returns a recording, which writeRecordingManifest
// writes and readRecording reads back equal, or throws io::IoError naming the file and field (the
// error a person sees); anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_file.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace {

// A folder with the frame files and camera.json a manifest may name.
std::filesystem::path preparedFolder(const std::filesystem::path& dir) {
  using namespace slicecap;
  std::filesystem::create_directories(dir);
  for (int i = 0; i < 4; ++i)
    fuzz::writeBytes(dir / ("frame-0000" + std::to_string(i) + ".png"), "not read here");
  vision::CameraModel camera;
  camera.intrinsics = {64, 48, 60.0, 60.0, 31.5, 23.5};
  fuzz::writeBytes(dir / "camera.json", io::cameraToJson(camera).dump());
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap;
  static const std::filesystem::path dir = preparedFolder(fuzz::scratchDir("recording") / "rec");
  static const std::filesystem::path again =
      preparedFolder(fuzz::scratchDir("recording") / "again");
  fuzz::writeBytes(dir / io::kRecordingManifest, fuzz::asText(data, size));
  io::Recording recording;
  try {
    recording = io::readRecording(dir);
  } catch (const io::IoError&) {
    return 0;
  }
  // An absolute calibration file or one outside the folder would resolve elsewhere in `again`.
  if (recording.calibrationFile && *recording.calibrationFile != "camera.json") return 0;
  io::writeRecordingManifest(again, recording);
  if (!(io::readRecording(again) == recording)) std::abort();
  return 0;
}
