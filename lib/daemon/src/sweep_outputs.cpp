// A sweep's raw-frame recording and texture, kept in line with the session manager's sweep.
#include "sweep_outputs.hpp"

#include <iostream>
#include <system_error>

#include "slicecap/control/reply_views.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::daemon {

namespace fs = std::filesystem;

void SweepOutputs::closeTexture() {
  texture_.reset();
  textureSlice_.reset();
}

void SweepOutputs::openTexture(const SliceId& slice) {
  const std::optional<fs::path> session = manager_.sessionDirectory();
  if (!capturesTexture() || !session) return;
  try {
    // The refusals each time: one whose set-aside failed mid-session is applied before the keep
    // rule, not only at the session's settling.
    texture_ = parts_.outputs->openTexture(slice, *session, manager_.refusals());
    textureSlice_ = slice;
  } catch (const std::exception& error) {
    manager_.pauseSweep(std::string("texture capture: ") + error.what());
  }
}

void SweepOutputs::reconcileTexture() {
  if (texture_ && textureSlice_ != manager_.sweepSlice()) closeTexture();
  settleTexture();
  // The swept slice's texture is open before its frames flow (also after a redo of the running
  // sweep closed it); if it cannot be, the sweep pauses here and no camera starts.
  if (manager_.capturing() && !texture_) openTexture(*manager_.sweepSlice());
}

void SweepOutputs::settleTexture() {
  const std::optional<fs::path> session = manager_.sessionDirectory();
  if (session == settledSession_) return;
  settledSession_ = session;
  if (!session || !parts_.outputs) return;
  // Before any of its sweeps opens the texture: a refusal journaled before a crash (or a move
  // that failed) is applied now, and the frames a run cut off replaced are judged.
  try {
    const std::size_t frames = parts_.outputs->settleTexture(*session, manager_.refusals());
    if (frames == 0) return;
    std::cerr << "slicecapd: texture: " << frames << " frames of refused sweep runs set aside "
              << "on opening the session (they were left in the texture)\n";
    manager_.addToError("texture: " + std::to_string(frames) +
                        " frames of refused sweep runs, left in the texture, set aside now");
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: texture: settling the session's refused runs: " << error.what()
              << "\n";
    manager_.addToError(std::string("texture: the frames of refused sweep runs could not all be "
                                    "set aside on opening the session (") +
                        error.what() +
                        "): the export may still copy some; restarting slicecapd tries again");
  }
}

void SweepOutputs::discardTexture(const SliceId& redone) {
  const std::optional<fs::path> session = manager_.sessionDirectory();
  // Only a redo the session manager will accept: none while another slice's sweep runs.
  const std::optional<SliceId> swept = manager_.sweepSlice();
  if (!session || (swept && *swept != redone)) return;
  if (textureSlice_ == redone) closeTexture();  // its index would still hold the frames
  // Refused runs' frames go with the slice's samples, as the redo discards those too. First: a
  // failure here refuses the redo with the slice's texture still whole.
  io::discardFolderDurably(*session / kTextureFolder / (folderName(redone) + io::kSetAsideSuffix));
  io::discardFolderDurably(*session / kTextureFolder / (folderName(redone) + io::kHeldSuffix));
  io::discardFolderDurably(*session / kTextureFolder / folderName(redone));
}

void SweepOutputs::beginTextureRun() {
  if (texture_) texture_->beginRun();
}

std::optional<capture::RunTextureFrames> SweepOutputs::textureRun() const {
  if (!texture_) return std::nullopt;
  return texture_->run();
}

void SweepOutputs::keepTextureRun() {
  if (!texture_) return;
  try {
    texture_->keepRun();
  } catch (const std::exception& error) {
    // Nothing is lost: the replaced frames stay held, read by nothing, until the next opening.
    std::cerr << "slicecapd: texture: deleting the frames a kept run replaced: " << error.what()
              << "\n";
  }
}

std::string SweepOutputs::setAsideTextureRun() {
  if (!texture_) return {};
  const std::string folder = folderName(*textureSlice_) + io::kSetAsideSuffix;
  try {
    const std::size_t frames = texture_->setAsideRun();
    if (frames == 0) return {};
    std::cerr << "slicecapd: texture: " << frames << " frames of the refused run set aside in "
              << folder << "\n";
    return "its " + std::to_string(frames) + " texture frames set aside in " +
           std::string(kTextureFolder) + "/" + folder + " (kept, not exported)";
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: texture: setting the refused run's frames aside: " << error.what()
              << "\n";
    // The refusal names the run's frames: the session's next opening sets them aside.
    return std::string("its texture frames could not all be set aside (") + error.what() +
           "): the export may still copy some until restarting slicecapd sets them aside";
  }
}

bool SweepOutputs::capturesTexture() const {
  return parts_.outputs && parts_.outputs->capturesTexture();
}

capture::FrameObserver SweepOutputs::textureObserver() {
  if (!capturesTexture()) return nullptr;
  return [this](const hal::Frame& frame, const capture::FrameOutcome& outcome,
                const std::vector<capture::AmbientTerm>& ambient) {
    if (!texture_ || !textureError_.empty()) return;
    try {
      texture_->add(frame, outcome, ambient);
    } catch (const io::IoError& error) {
      textureError_ = std::string("texture storage error: ") + error.what();
    } catch (const std::exception& error) {
      textureError_ = std::string("texture capture error: ") + error.what();
    }
  };
}

void SweepOutputs::pauseOnTextureError() {
  if (textureError_.empty()) return;
  // The sample is kept; the texture stops with the sweep until the person frees space.
  manager_.pauseSweep(textureError_);
  textureError_.clear();
}

fs::path SweepOutputs::recordingDirectory(const fs::path& session, const SliceId& slice) {
  return session / "recordings" / folderName(slice);
}

void SweepOutputs::reconcileRecorder(const std::optional<SliceId>& cameraSlice) {
  const std::optional<SliceId> swept = manager_.sweepSlice();
  if (recorder_ && recorderSlice_ != swept) {
    retiredRecorders_.push_back(std::move(recorder_));
    recorderSlice_.reset();
  }
  std::erase_if(retiredRecorders_, [](const auto& retired) { return retired->idle(); });
  if (recorder_ || !cameraSlice || !parts_.outputs) return;
  const std::optional<fs::path> session = manager_.sessionDirectory();
  if (!session) return;
  std::optional<io::Recording> header = parts_.outputs->recordingHeader(*cameraSlice);
  if (!header) return;  // record_frames is off
  header->slice = io::RecordedSlice{*cameraSlice, kAxialOffsetDeg};
  recorder_ = std::make_unique<FrameRecorder>(recordingDirectory(*session, *cameraSlice),
                                              std::move(*header), parts_.recordQueueFrames);
  recorderSlice_ = cameraSlice;
}

void SweepOutputs::discardRecording(const SliceId& redone) {
  if (recorderSlice_ == redone) {
    recorder_.reset();  // waits for its writer: a person's command, not the frame loop
    recorderSlice_.reset();
  }
  retiredRecorders_.clear();
  if (const std::optional<fs::path> session = manager_.sessionDirectory()) {
    std::error_code ignored;
    fs::remove_all(recordingDirectory(*session, redone), ignored);
  }
}

void SweepOutputs::record(hal::Frame&& frame) {
  if (recorder_) recorder_->offer(std::move(frame));
}

void SweepOutputs::setDecoding(const io::RecordedDecoding& decoding) {
  if (recorder_) recorder_->setDecoding(decoding);
}

void SweepOutputs::recordBracket(SweepDecoding& decided, const SliceId& slice) {
  if (decided.bracketFrames.empty() || !parts_.outputs) return;
  const std::optional<fs::path> session = manager_.sessionDirectory();
  if (!session) return;
  std::optional<io::Recording> header = parts_.outputs->recordingHeader(slice);
  if (!header) return;  // record_frames is off
  const fs::path folder = *session / kBracketFolder / folderName(slice);
  fs::path directory;
  for (int run = 1;; ++run) {
    directory = folder / ("run-" + std::to_string(run));
    std::error_code ignored;
    if (!fs::exists(directory, ignored)) break;
  }
  header->slice.reset();
  header->createdBy += " (response bracket)";
  header->decoding = decided.decoding;
  auto writer = std::make_unique<FrameRecorder>(directory, std::move(*header),
                                                decided.bracketFrames.size());
  writer->setDecoding(decided.decoding);
  for (hal::Frame& frame : decided.bracketFrames) writer->offer(std::move(frame));
  retiredRecorders_.push_back(std::move(writer));  // writes on its thread, then is dropped
}

std::optional<control::RecordingView> SweepOutputs::recordingView() const {
  if (!recorder_) return std::nullopt;
  const RecorderStatus s = recorder_->status();
  control::RecordingView recording{s.directory.string(), s.framesWritten, s.framesQueued,
                                   s.framesDropped, std::nullopt};
  if (!s.error.empty()) recording.error = "recording stopped: " + s.error;
  return recording;
}

std::optional<control::TextureProgressView> SweepOutputs::textureView() const {
  if (!texture_) return std::nullopt;
  return texture_->status();
}

}  // namespace slicecap::daemon
