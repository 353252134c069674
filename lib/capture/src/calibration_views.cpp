// The marker corners of every frame of recordings, as views for the camera calibration.
#include "slicecap/capture/camera_calibration.hpp"
#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/hal/recorded_frame.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::capture {

std::vector<CalibrationView> calibrationViewsOf(
    const std::vector<std::filesystem::path>& recordings, int* widthPx, int* heightPx,
    int* unreadable) {
  std::vector<CalibrationView> views;
  *widthPx = 0;
  *heightPx = 0;
  *unreadable = 0;
  // Decimation 2 finds the quads, edge refinement puts the corners on the full-resolution image;
  // the retry at full resolution keeps the steep views, which carry the focal length.
  MarkerDetector detector;
  for (const auto& directory : recordings) {
    const io::Recording recording = io::readRecording(directory);
    const auto& size = recording.camera.intrinsics;
    if (*widthPx == 0) {
      *widthPx = size.widthPx;
      *heightPx = size.heightPx;
    } else if (size.widthPx != *widthPx || size.heightPx != *heightPx) {
      throw CalibrationError(directory.string() + ": frames of " + std::to_string(size.widthPx) +
                             " x " + std::to_string(size.heightPx) +
                             ", the first recording's are " + std::to_string(*widthPx) + " x " +
                             std::to_string(*heightPx) +
                             ": one calibration is for one camera mode");
    }
    for (const io::RecordedFrame& entry : recording.frames) {
      hal::Frame frame;
      try {
        frame.image = io::readPng(io::framePath(directory, entry));
      } catch (const io::IoError&) {
        ++*unreadable;
        continue;
      }
      if (frame.image.width != *widthPx || frame.image.height != *heightPx) {
        ++*unreadable;
        continue;
      }
      hal::setRecordedEncoding(frame, recording);
      CalibrationView view;
      view.source = (directory / entry.file).string();
      for (const DetectedMarker& marker : detector.detect(frame)) {
        const vision::Marker* geometry = recording.target.findMarker(marker.id);
        if (!geometry) continue;
        for (int c = 0; c < 4; ++c)
          view.points.push_back(
              {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
      }
      views.push_back(std::move(view));
    }
  }
  return views;
}

}  // namespace slicecap::capture
